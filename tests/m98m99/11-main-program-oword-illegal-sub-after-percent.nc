%
(FMSVM M98M99 TEST 11-MAIN-PROGRAM-OWORD, ILLEGAL SUB-AFTER-PERCENT)
(ORIGINAL: LINUXCNC TESTS/INTERP/M98M99/11-MAIN-PROGRAM-OWORD/)
(TEST-ILLEGAL-SUB-AFTER-PERCENT.NGC)
(CHANGED: O2 CALL IS M98 P2, O2 SUB IS O2, O2 ENDSUB IS M99.)
(illegal example)
(Define sub after percent [= after EOF])
O1 (main program begin)
G0 X1Y2
(calling sub 2)
M98 P2
(returned from sub 2)
%
(Nothing should follow % sign)

(From http://linuxcnc.org/docs/html/gcode/overview.html#_overview    )
(    The useful contents of a file demarcated by percents stop after )
(    the second percent line. Anything after that is ignored.        )

(From Smid 3rd Ed. p. 62)
(    The percent sign (%) after M30 is a special _stop_code_.  This  )
(    symbol terminates the loading of a program from an external     )
(    device.  It is also called the _end-of-file_marker_.            )

O2 (subprogram begin) (program end signaled by O2 sub)
(in sub 2)
G0 Z3
(returning from sub 2)
M99
