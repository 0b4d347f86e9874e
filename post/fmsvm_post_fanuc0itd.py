# The turning library reads the machine cycles below from this comment (BEGIN_MACHINE_CYCLES …
# END_MACHINE_CYCLES). `fmsvm dialects --launcher fanuc0itd` writes this file. A raw string: no
# text of the catalogue is read by Python as an escape.
r'''
BEGIN_MACHINE_CYCLES

BEGIN_CYCLE 71
NAME "Stock removal in turning (G71)"
COMMENT "Fanuc 0i-TD G71: the profile between P and Q (type II when its first block names X and Z)"
TYPE Turning
PARAMETERS
U O "depth of cut (radius)"
R O "retract"
DU S "finishing allowance in X (diameter)"
DW S "finishing allowance in Z"
F S "feed"
TOOL_DEMANDS "Chisel"
PROFIL_DEMANDS ""
END_CYCLE

BEGIN_CYCLE 72
NAME "Stock removal in facing (G72)"
COMMENT "Fanuc 0i-TD G72: the profile between P and Q"
TYPE Turning
PARAMETERS
W O "depth of cut"
R O "retract"
DU S "finishing allowance in X (diameter)"
DW S "finishing allowance in Z"
F S "feed"
TOOL_DEMANDS "Chisel"
PROFIL_DEMANDS ""
END_CYCLE

BEGIN_CYCLE 73
NAME "Pattern repeating (G73)"
COMMENT "Fanuc 0i-TD G73: the profile between P and Q, copied inwards"
TYPE Turning
PARAMETERS
I O "relief in X (radius)"
K O "relief in Z"
D O "number of passes"
DU S "finishing allowance in X (diameter)"
DW S "finishing allowance in Z"
F S "feed"
TOOL_DEMANDS "Chisel"
PROFIL_DEMANDS ""
END_CYCLE

BEGIN_CYCLE 74
NAME "Face peck drilling (G74)"
COMMENT "Fanuc 0i-TD G74 on the spindle's axis: pecks of Q to the hole's end"
TYPE Drilling
PARAMETERS
E O "retract after each peck"
Q O "peck depth (mm)"
F S "feed"
TOOL_DEMANDS "Drill"
END_CYCLE

BEGIN_CYCLE 76
NAME "Multiple threading (G76)"
COMMENT "Fanuc 0i-TD G76: X the root diameter, the thread's height from the library"
TYPE Threading
PARAMETERS
M O "finishing passes"
A O "tool angle (80 60 55 30 29 0)"
DMIN O "minimum depth of cut (mm)"
D O "finishing allowance (mm)"
DD O "first depth of cut (mm)"
TOOL_DEMANDS "Chisel"
PROFIL_DEMANDS "Cylinder"
END_CYCLE
END_MACHINE_CYCLES
'''
"""fmsvm as a postprocessor of the turning library («Модуль ЧПУ. Токарная обработка») for fanuc0itd:
FANUC Series 0i-TD lathe: Fanuc's format, G4 X seconds, lathe cycles G70–G76 G90 G92 G94.

The library starts this script with the path of its input.tmp; fmsvm writes output.tmp (and
path.tmp, the path inside the cycles) beside it and prints OK, or the errors one a line, which this
script passes on. Put this file in the library's POSTPROCESSORS folder and fmsvm beside it, on the
PATH, or named by FMSVM (its full path). See docs/postprocessor.md.
"""
import os
import shutil
import subprocess
import sys

CONTROL = "fanuc0itd"
# More options of `fmsvm post`: "--moves" writes every cycle in elementary moves; "--max-rpm", "2500"
# gives the machine's highest spindle speed, the clamp written before constant surface speed (G96),
# which is refused without it on a control that has G96. fmsvm reads its output back and compares
# it with the library's program before it says OK ("--no-verify" would turn that off).
OPTIONS = []
# The library waits 10 s; fmsvm converts in far less (its input is at most 16 MiB).
TIMEOUT_S = 9


def find_fmsvm():
    """fmsvm: FMSVM's path, else beside this script, else on the PATH; and where it looked."""
    named = os.environ.get("FMSVM")
    if named:
        if os.path.isfile(named):
            return named, []
        return None, ["FMSVM names %s, which is not a file" % named]
    here = os.path.dirname(os.path.abspath(__file__))
    for name in ("fmsvm.exe", "fmsvm") if os.name == "nt" else ("fmsvm",):
        beside = os.path.join(here, name)
        if os.path.isfile(beside) and os.access(beside, os.X_OK):
            return beside, []
    found = shutil.which("fmsvm")
    if found:
        return found, []
    return None, [
        "FMSVM is not set",
        "not in this script's folder %s" % here,
        "not on the PATH (%s)" % os.environ.get("PATH", ""),
    ]


def main():
    if len(sys.argv) < 2:
        print("fmsvm_post: give the path of input.tmp")
        return 2
    fmsvm, looked = find_fmsvm()
    if fmsvm is None:
        print("fmsvm_post: fmsvm not found: " + "; ".join(looked))
        print("fmsvm_post: put fmsvm beside this script or on the PATH, or set FMSVM to its full path")
        return 2
    try:
        done = subprocess.run(
            [fmsvm, "post", "--dialect", CONTROL] + OPTIONS + [sys.argv[1]],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            timeout=TIMEOUT_S,
        )
    except OSError as e:
        print("fmsvm_post: %s could not be started: %s" % (fmsvm, e))
        return 2
    except subprocess.TimeoutExpired:
        print("fmsvm_post: fmsvm took more than %d s" % TIMEOUT_S)
        return 2
    sys.stdout.write(done.stdout.decode("utf-8", "replace"))
    return done.returncode


if __name__ == "__main__":
    sys.exit(main())
