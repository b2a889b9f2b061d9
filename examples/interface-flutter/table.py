"""Tables of docs/interface-flutter.md from the cea.json files of run.sh.

Usage: python3 table.py OUT [LEVELS [SETTINGS]], e.g. table.py out 1,2,4,8 rigid,ge01
"""
import json, sys, os
out = sys.argv[1]
levels = [int(x) for x in (sys.argv[2] if len(sys.argv) > 2 else "1,2,4,8").split(',')]
settings = (sys.argv[3] if len(sys.argv) > 3 else "rigid,mu035,ge01,kn1e9,kn1e8,kn1e7,kn1e6,kn1e5").split(',')
for st in settings:
    print(f"\n### {st}\n")
    print("| level | h (in) | gaps | reduced DOFs | unstable in band / above | top unstable f (kHz) | max Re p (1/s) | at f (kHz) | ζ there | unstable in band: f (Hz), Re p (1/s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for f in levels:
        p = f"{out}/L{f}-{st}/cea.json"
        if not os.path.exists(p):
            print(f"| {f} | missing |"); continue
        d = json.load(open(p))
        ob = d['outside_band']; s = d['stats']
        inb = [m for m in d['modes'] if m['unstable']]
        allu = inb + ob['unstable']
        top = max(allu, key=lambda m: m['real_part']) if allu else None
        fmax = max([m['frequency_hz'] for m in inb] + ([ob['max_unstable_frequency_hz']] if ob.get('max_unstable_frequency_hz') else []) or [0])
        h = 3.5/3/f
        ib = '; '.join('%.0f, %.3g' % (m['frequency_hz'], m['real_part']) for m in sorted(inb, key=lambda m: -m['real_part'])[:3])
        rb = max([m['real_part'] for m in inb], default=float('nan'))
        print(f"| {f} | {h:.3f} | {d['steady_state']['contact']['n_gaps']} | {s['n']} | {len(inb)} / {ob['n_unstable']} | {fmax/1e3:.1f} | {top['real_part'] if top else 0:.4g} | {top['frequency_hz']/1e3 if top else 0:.1f} | {top['damping_ratio'] if top else 0:.3f} | {ib} |")
