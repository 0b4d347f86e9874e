%
O1 (Main program begin)
(FMSVM M98M99 TEST 12-M99-ENDLESS-MAIN-PROGRAM)
(ORIGINAL: LINUXCNC TESTS/INTERP/M98M99/12-M99-ENDLESS-MAIN-PROGRAM/TEST.NGC)
(CHANGED: AN OPENING PERCENT LINE IS ADDED. THE MAIN PROGRAM NUMBER O1,)
(WHICH LINUXCNC TAKES AS THE TITLE OF THE MAIN PROGRAM IN THE MIDDLE OF)
(THE FILE, IS THE FIRST LINE: ON FANUC AN O LINE STARTS A NEW PROGRAM, AND)
(M99 IN THE MAIN PROGRAM GOES BACK TO ITS START, THE COUNTER INCLUDED, AS IT)
(DOES IN LINUXCNC TASK. O1000 IF ... O1000 ENDIF IS AN IF GOTO AROUND THE)
(BLOCK WITH THE CONDITION NEGATED. THE PRINT COMMENTS ARE DPRNTS, WITH)
(POPEN FIRST AND PCLOS BEFORE M30. THE QUOTES IN THE STOP MESSAGE ARE DROPPED.)
(Endless program)

(In a standalone interpreter, this should probably exit)
(at the main program M99.  In task, the main program M99)
(should cause an endless loop, terminated by a counter.)

(*****************************************************)
(Don't *actually* run this program infinitely!)
POPEN
(Stop after)#101 = 3(loops in case of failure)
#100 = [#100 + 1]  (Counter, assume it starts at 0)
IF [#100 LE #101] GOTO 1000 (was: O1000 if [#100 GT #101])
  DPRNT[Stopping*program*after*#101[40]*loops]
  #100 = 0  (Reset counter)
  PCLOS
  M30  (End program)
N1000 (was: O1000 endif)
(*****************************************************)
DPRNT[*X*Loop*number*#100[44]]
G1 X1 F40 (Junk move...)
M98 P100 (Call junk subprogram)
G1 X5 (Another junk move...)
M99 (Main program endless loop)

(*****************************************************)
O100 (Junk subprogram begin)
G1 Y-4 (Subprogram junk move...)
M99 (Return to main program)

%
