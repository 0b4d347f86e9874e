(FMSVM M98M99 TEST 11-MAIN-PROGRAM-OWORD, ILLEGAL NO-M30-BEFORE-OSUB)
(ORIGINAL: LINUXCNC TESTS/INTERP/M98M99/11-MAIN-PROGRAM-OWORD/)
(TEST-ILLEGAL-NO-M30-BEFORE-OSUB.NGC)
(CHANGED: O2 CALL IS M98 P2, O2 SUB IS O2, O2 ENDSUB IS M99.)
(illegal example)
(Define rs274-style sub before numeric O-word main program end)
O1 (main program begin)
G0 X1Y2
(calling sub 2)
M98 P2
(returned from sub 2)

(Illegal:  O-sub with no M02 or M30 terminating main)
O2 (subprogram begin)
(in sub 2)
G0 Z3
(returning from sub 2)
M99
