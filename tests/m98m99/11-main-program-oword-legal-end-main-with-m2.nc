(FMSVM M98M99 TEST 11-MAIN-PROGRAM-OWORD, LEGAL END-MAIN-WITH-M2)
(ORIGINAL: LINUXCNC TESTS/INTERP/M98M99/11-MAIN-PROGRAM-OWORD/)
(TEST-LEGAL-END-MAIN-WITH-M2.NGC)
(CHANGED: THE RS274NGC SUBROUTINE IS A FANUC SUBPROGRAM: O2 CALL IS M98 P2,)
(O2 SUB IS O2, O2 ENDSUB IS M99. O2 USES NO VARIABLES, SO M98 AND G65 ARE)
(THE SAME HERE. LIKE THE ORIGINAL, THE FILE HAS NO PERCENT LINES.)
(legal example)
(Main program defined with numeric O-word title, terminated by M2)
O1 (main program begin)
G0 X1Y2
(calling sub 2)
M98 P2
(returned from sub 2)
M2 (end of main)
(should never get here)

O2 (subprogram begin) (program end signaled by O2 sub)
(in sub 2)
G0 Z3
(returning from sub 2)
M99
