%
(FMSVM M98M99 TEST 11-MAIN-PROGRAM-OWORD, LEGAL END-MAIN-WITH-PERCENT)
(ORIGINAL: LINUXCNC TESTS/INTERP/M98M99/11-MAIN-PROGRAM-OWORD/)
(TEST-LEGAL-END-MAIN-WITH-PERCENT.NGC)
(CHANGED: O2 CALL IS M98 P2, O2 SUB IS O2, O2 ENDSUB IS M99. THE ORDER IS)
(KEPT: THE SUBPROGRAM COMES BEFORE THE MAIN PROGRAM O1, WHICH HAS NO M30.)
(THAT ORDER HAS NO FANUC COUNTERPART, SEE README: ON FANUC THE FIRST)
(PROGRAM OF THE FILE, HERE O2, IS WHAT RUNS.)
(legal example)
(Main program defined with numeric O-word title, terminated by percent)
O2 (subprogram begin) (program end signaled by O2 sub)
(in sub 2)
G0 Z3
(returning from sub 2)
M99

O1 (main program begin)
G0 X1Y2
(calling sub 2)
M98 P2
(returned from sub 2)

(end of main signaled by percent)
%
