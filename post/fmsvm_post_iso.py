# The turning library reads the machine cycles below from this comment (BEGIN_MACHINE_CYCLES …
# END_MACHINE_CYCLES). `fmsvm dialects --launcher iso` writes this file. A raw string: no
# text of the catalogue is read by Python as an escape.
r'''
BEGIN_MACHINE_CYCLES

BEGIN_CYCLE 71
NAME "Продольное точение (в элементарных перемещениях)"
COMMENT "fmsvm: проходы вдоль Z до контура, чистовые проходы"
TYPE Turning
PARAMETERS
I S "глубина резания за проход (на радиус)"
J S "количество проходов"
U S "припуск на чистовой проход по X (на диаметр)"
W S "припуск на чистовой проход по Z"
VP S "количество чистовых проходов"
C S "главный угол резца в плане"
E S "отвод после прохода" 0.5
F S "скорость подачи"
TOOL_DEMANDS "Chisel"
PROFIL_DEMANDS "TrapecG1 | TrapecG2 | TrapecG3 | TrapecG4"
END_CYCLE

BEGIN_CYCLE 72
NAME "Подрезка торца (в элементарных перемещениях)"
COMMENT "fmsvm: проходы вдоль X до контура, чистовые проходы"
TYPE Turning
PARAMETERS
I S "глубина резания за проход"
J S "количество проходов"
U S "припуск на чистовой проход по X (на диаметр)"
W S "припуск на чистовой проход по Z"
VP S "количество чистовых проходов"
C S "главный угол резца в плане"
E S "отвод после прохода" 0.5
F S "скорость подачи"
TOOL_DEMANDS "Chisel"
PROFIL_DEMANDS "TrapecV1 | TrapecV2 | TrapecV3 | TrapecV4"
END_CYCLE

BEGIN_CYCLE 76
NAME "Нарезание резьбы резцом (в элементарных перемещениях)"
COMMENT "fmsvm: проходы с глубиной по закону √n, чистовые проходы"
TYPE Threading
PARAMETERS
P S "глубина первого прохода (на радиус)"
Q S "наименьшая глубина прохода" 0.05
R S "припуск на чистовой проход"
VP S "количество чистовых проходов" 1
A S "угол врезания по боковой стороне (0: радиальное)"
TOOL_DEMANDS "Chisel"
PROFIL_DEMANDS "Cylinder | Cone"
END_CYCLE

BEGIN_CYCLE 83
NAME "Глубокое сверление (в элементарных перемещениях)"
COMMENT "fmsvm: сверление с выводом для дробления стружки"
TYPE Drilling
PARAMETERS
P S "глубина сверления за проход"
E S "отвод после прохода" 0.5
F S "скорость подачи"
TOOL_DEMANDS "Drill"
END_CYCLE
END_MACHINE_CYCLES
'''
"""fmsvm as a postprocessor of the turning library («Модуль ЧПУ. Токарная обработка») for iso:
ISO 6983 word address: % start, no O word, N renumbered, G4 X seconds, M30 end.

The library starts this script with the path of its input.tmp; fmsvm writes output.tmp (and
path.tmp, the path inside the cycles) beside it and prints OK, or the errors one a line, which this
script passes on. Put this file in the library's POSTPROCESSORS folder and fmsvm beside it, on the
PATH, or named by FMSVM (its full path). See docs/postprocessor.md.
"""
import os
import shutil
import subprocess
import sys

CONTROL = "iso"
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
