#!/usr/bin/env python3
"""printnorm: reduce printed text to comparable tokens, one output line per printed line.

Used for the print checks of tests/m98m99: LinuxCNC's (PRINT,...) lines in an `rs274 -g` trace and the
DPRNT records fmsvm writes (--print FILE) are both reduced to words [A-Z]+ and numbers (a number with a
decimal point as %.4f, so 42.010000 and 42.0100 agree); everything else (spaces, ':', '=', ';', '[', '>',
the DC2/DC4 bytes of POPEN/PCLOS) is dropped, and so are lines left empty.

  printnorm.py trace FILE   the print lines of an rs274 trace (lines that are not `   N N..... CANON(...)`
                            and not `executing`)
  printnorm.py prn FILE     the lines of a DPRNT output file
"""
import re
import sys

TOKEN = re.compile(r"[A-Z]+|-?\d+(?:\.\d+)?")
CANON = re.compile(r"^\s*\d*\s*N\.\.\.\.\. ")


def norm(line):
    out = []
    for t in TOKEN.findall(line.upper()):
        if "." in t:
            t = "%.4f" % (float(t) + 0.0)
            t = "0.0000" if t == "-0.0000" else t
        out.append(t)
    return " ".join(out)


def main(argv):
    if len(argv) != 3 or argv[1] not in ("trace", "prn"):
        print(__doc__)
        return 2
    with open(argv[2], encoding="latin-1") as f:
        lines = f.read().splitlines()
    for line in lines:
        if argv[1] == "trace" and (CANON.match(line) or line.strip() == "executing"):
            continue
        line = line.replace("\x12", "").replace("\x14", "")
        n = norm(line)
        if n:
            print(n)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
