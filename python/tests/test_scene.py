"""Scenes: the constructors agree, `set` validates and copies, errors carry the CLI's message,
scenes pickle."""

from __future__ import annotations

import pickle
import tomllib

import pytest

import squeal
from conftest import EXAMPLES, ROOT

TINY = EXAMPLES / "transient" / "tiny-brake.toml"


def test_constructors_agree():
    a = squeal.Scene.from_file(TINY)
    b = squeal.Scene.from_toml(TINY.read_text(), base_dir=TINY.parent)
    c = squeal.Scene.from_dict(tomllib.loads(TINY.read_text()), base_dir=TINY.parent)
    assert a == b == c
    assert a.components == ["rotor", "pad"]
    assert a.model_source == "mesh"
    d = a.to_dict()
    assert d["friction"]["law"]["mu0"] == 0.6
    assert squeal.Scene.from_dict(d, base_dir=TINY.parent) == a


def test_set_copies_and_validates():
    a = squeal.Scene.from_file(TINY)
    b = a.set("friction.law.mu0", 0.5)
    assert b.to_dict()["friction"]["law"]["mu0"] == 0.5
    assert a.to_dict()["friction"]["law"]["mu0"] == 0.6
    assert squeal.Scene.from_file(TINY, set={"friction.law.mu0": 0.5}) == b
    with pytest.raises(squeal.SceneError, match="mu0x"):
        a.set("friction.law.mu0x", 0.5)


def test_error_message_is_the_clis(cli):
    # The same bad override through the CLI and through Scene.from_file.
    _, p = cli("check", str(TINY), "--set", "transient.rtol1=-1", check=False, out=False)
    assert p.returncode == 1
    line = p.stderr.strip().splitlines()[-1]
    assert line.startswith("squeal: error: ")
    with pytest.raises(squeal.SceneError) as e:
        squeal.Scene.from_file(TINY, set={"transient.rtol1": -1})
    assert str(e.value) == line[len("squeal: error: "):]


def test_unknown_key_in_dict_names_it():
    d = tomllib.loads(TINY.read_text())
    d["friction"]["vtoll"] = 1.0
    with pytest.raises(squeal.SceneError, match="vtoll"):
        squeal.Scene.from_dict(d)


def test_missing_file_is_input_error():
    with pytest.raises(squeal.InputError, match="no-such-scene.toml"):
        squeal.Scene.from_file("no-such-scene.toml")


def test_pickle_round_trip():
    a = squeal.Scene.from_file(TINY).set("rotor.rpm", 12.0)
    b = pickle.loads(pickle.dumps(a))
    assert a == b
    assert b.base_dir == a.base_dir
