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


def test_errors_carry_the_key_and_the_file():
    # SceneError.field names the key of a bad value, of an unknown key and of an override.
    a = squeal.Scene.from_file(TINY)
    with pytest.raises(squeal.SceneError) as e:
        squeal.Scene.from_file(TINY, set={"transient.rtol1": -1})
    assert e.value.field == "transient.rtol1"
    assert e.value.path is None
    with pytest.raises(squeal.SceneError) as e:
        a.set("friction.law.mu0x", 0.5)
    assert e.value.field is not None and "mu0x" in e.value.field
    # A scene file that does not parse: no field, its path.
    with pytest.raises(squeal.SceneError) as e:
        squeal.Scene.from_toml("[rotor\n", base_dir=TINY.parent)
    assert e.value.field is None


def test_a_missing_file_is_a_file_not_found_error(tmp_path):
    missing = tmp_path / "no-such-scene.toml"
    with pytest.raises(FileNotFoundError) as e:
        squeal.Scene.from_file(missing)
    assert isinstance(e.value, squeal.InputError)
    assert isinstance(e.value, squeal.InputFileNotFound)
    assert e.value.errno == 2
    assert e.value.filename == str(missing) == e.value.path
    # The message is the command line's.
    assert str(missing) in str(e.value)
