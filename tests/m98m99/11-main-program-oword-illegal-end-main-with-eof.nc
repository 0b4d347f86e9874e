(FMSVM M98M99 TEST 11-MAIN-PROGRAM-OWORD, ILLEGAL END-MAIN-WITH-EOF)
(ORIGINAL: LINUXCNC TESTS/INTERP/M98M99/11-MAIN-PROGRAM-OWORD/)
(TEST-ILLEGAL-END-MAIN-WITH-EOF.NGC)
(CHANGED: O2 CALL IS M98 P2, O2 SUB IS O2, O2 ENDSUB IS M99. THE ORDER IS)
(KEPT: THE SUBPROGRAM COMES BEFORE THE MAIN PROGRAM O1, WHICH HAS NO M30,)
(AND THE FILE HAS NO PERCENT LINES. SEE README.)
(legal example)
(Main program defined with numeric O-word title, terminated by EOF)
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

(end of main signaled by EOF)
