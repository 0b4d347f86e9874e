#!/usr/bin/env python3
"""kmoves: canonical moves of an rs274 trace, as `ncmotion.py moves` prints them, extended for the
kernel tests (tests/kernel.rs):

  * arcs in every plane: SELECT_PLANE is followed; ARC_FEED's arguments are in the plane's order
    (XY: X Y; XZ: Z X; YZ: Y Z, the third end being the normal axis). An XY arc is printed as ncmotion
    prints it, `G2 X Y Z CX CY`; a ZX arc `G2 X Y Z CX CZ G18`; a YZ arc `G2 X Y Z CY CZ G19`.
  * the tool length offset: USE_TOOL_LENGTH_OFFSET is added to every position, as a Fanuc control's
    resolved motion (the path of the spindle's gauge point, which `fmsvm run --resolve` writes) has it.
  * SET_G5X_OFFSET / SET_G92_OFFSET are applied as in ncmotion: moves are in the frame of G54.

For a trace of XY arcs without a tool length offset the output is exactly ncmotion's.
Usage: kmoves.py TRACE
"""
import re
import sys

CANON = re.compile(
    r"(STRAIGHT_TRAVERSE|STRAIGHT_FEED|ARC_FEED|SET_G5X_OFFSET|SET_G92_OFFSET|SELECT_PLANE|"
    r"USE_TOOL_LENGTH_OFFSET)\(([^)]*)\)"
)


def moves(text):
    pos = [0.0, 0.0, 0.0]
    offsets = {1: [0.0, 0.0, 0.0]}
    active, shift, tlo = 1, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    plane = "XY"
    out = []

    def frame():
        g54 = offsets.get(1, [0.0] * 3)
        return [offsets.get(active, [0.0] * 3)[i] + shift[i] - g54[i] + tlo[i] for i in range(3)]

    for m in CANON.finditer(text):
        kind, args = m.group(1), [a.strip() for a in m.group(2).split(",")]
        if kind == "SET_G5X_OFFSET":
            active = int(args[0])
            offsets[active] = [float(a) for a in args[1:4]]
            continue
        if kind == "SET_G92_OFFSET":
            shift = [float(a) for a in args[:3]]
            continue
        if kind == "SELECT_PLANE":
            plane = args[0].replace("CANON_PLANE_", "")
            continue
        if kind == "USE_TOOL_LENGTH_OFFSET":
            tlo = [float(a) for a in args[0].split()[:3]]
            continue
        d = frame()
        if kind.startswith("STRAIGHT"):
            target = [float(a) + d[i] for i, a in enumerate(args[:3])]
            if any(abs(t - p) > 1e-9 for t, p in zip(target, pos)):
                out.append(("G0" if kind == "STRAIGHT_TRAVERSE" else "G1", *target))
            pos = target
            continue
        e1, e2, c1, c2, rot, en = (float(a) for a in args[:6])
        g = "G3" if rot > 0 else "G2"
        if plane == "XY":
            target = [e1 + d[0], e2 + d[1], en + d[2]]
            out.append((g, *target, c1 + d[0], c2 + d[1]))
        elif plane == "XZ":
            target = [e2 + d[0], en + d[1], e1 + d[2]]
            out.append((g, *target, c2 + d[0], c1 + d[2], "G18"))
        else:
            target = [en + d[0], e1 + d[1], e2 + d[2]]
            out.append((g, *target, c1 + d[1], c2 + d[2], "G19"))
        pos = target
    return out


def fmt(m):
    return " ".join([m[0]] + [v if isinstance(v, str) else "%.4f" % v for v in m[1:]])


if __name__ == "__main__":
    with open(sys.argv[1], encoding="utf-8", errors="replace") as f:
        for mv in moves(f.read()):
            print(fmt(mv))
