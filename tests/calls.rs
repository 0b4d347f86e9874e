//! Subprograms and macro calls (macro-b-rules C2–C12, V3, V12), DPRNT/BPRNT (O1–O5), #3006, timers.
//! Expected values are worked out by hand from the rows.

use crate::common;

use common::{Failure, alarm_of, expand, expand_full, ok};
use fmsvm_compiler::Options;
use fmsvm_emit::literal;
use fmsvm_vm::RunOptions;

/// A main program followed by the given subprograms in the same file.
fn with(main: &str, subs: &str) -> String {
    format!("%\nO1\n{main}\nM30\n{subs}\n%\n")
}

fn var(src: &str, n: u32) -> Option<f64> {
    ok(src).var(n)
}

#[test]
fn c2_argument_specification_i() {
    let sub = "O9000\n#100=#1\n#101=#2\n#102=#24\n#103=#26\n#104=#13\n#105=#9\nIF[#3 EQ #0]THEN #106=1\nM99";
    let e = ok(&with("G65 P9000 A1. B2. X3. Z4. M5. F6.", sub));
    assert_eq!(
        [100, 101, 102, 103, 104, 105, 106].map(|n| e.var(n)),
        [
            Some(1.0),
            Some(2.0),
            Some(3.0),
            Some(4.0),
            Some(5.0),
            Some(6.0),
            Some(1.0)
        ]
    );
}

#[test]
fn c3_argument_specification_ii() {
    let sub = "O9001\n#100=#4\n#101=#5\n#102=#6\n#103=#7\n#104=#8\n#105=#9\n#106=#1\nM99";
    let e = ok(&with("G65 P9001 A1. I2. J3. K4. I5. J6. K7.", sub));
    assert_eq!(
        [100, 101, 102, 103, 104, 105, 106].map(|n| e.var(n)),
        [
            Some(2.0),
            Some(3.0),
            Some(4.0),
            Some(5.0),
            Some(6.0),
            Some(7.0),
            Some(1.0)
        ]
    );
}

#[test]
fn c4_mixed_specifications_later_wins() {
    // The Fanuc manual's example: G65 A1.0 B2.0 I-3.0 I4.0 D5.0 P1000 → #1=1 #2=2 #4=-3 #7=5.
    let sub = "O1000\n#100=#1\n#101=#2\n#102=#4\n#103=#7\nM99";
    let e = ok(&with("G65 A1.0 B2.0 I-3.0 I4.0 D5.0 P1000", sub));
    assert_eq!(
        [100, 101, 102, 103].map(|n| e.var(n)),
        [Some(1.0), Some(2.0), Some(-3.0), Some(5.0)]
    );
}

#[test]
fn c11_sets_with_missing_letters() {
    // I1. I2. J3.: set 1 has only I (#4), set 2 is I J (#7 #8); #5 stays vacant.
    let sub = "O9002\n#100=#4\n#101=#5\n#102=#7\n#103=#8\nM99";
    let e = ok(&with("G65 P9002 I1. I2. J3.", sub));
    assert_eq!(
        [100, 101, 102, 103].map(|n| e.var(n)),
        [Some(1.0), None, Some(2.0), Some(3.0)]
    );
}

#[test]
fn c5_arguments_without_point_under_input_type_i() {
    let sub = "O9003\n#100=#24\n#101=#26\nM99";
    let src = with("G65 P9003 X10 Z10.", sub);
    let o = common::Setup {
        rules: fmsvm_canon::decode::InputRules {
            decimal: fmsvm_canon::decode::DecimalInput::Increment,
            ..Default::default()
        },
        ..Default::default()
    };
    let e = expand_full(&src, &[], o, RunOptions::default(), Options::default()).expect("runs");
    assert_eq!([e.var(100), e.var(101)], [Some(0.01), Some(10.0)]);
    // Calculator input (the default): X10 is 10.
    assert_eq!(var(&src, 100), Some(10.0));
}

#[test]
fn v12_locals_of_m98_are_shared_of_g65_restored() {
    let sub100 = "O100\n#1=#1+1\nM99";
    let sub200 = "O200\n#1=#1+1\n#101=#1\nM99";
    let e = ok(&with("#1=5\nM98 P100\n#100=#1", sub100));
    assert_eq!(e.var(100), Some(6.0));
    let e = ok(&with("#1=5\nG65 P200 A9.\n#100=#1", sub200));
    assert_eq!([e.var(100), e.var(101)], [Some(5.0), Some(10.0)]);
}

#[test]
fn c10_g65_repeat_keeps_the_locals_between_runs() {
    let e = ok(&with("G65 P9000 L3 A1.", "O9000\n#1=#1+1\n#100=#1\nM99"));
    assert_eq!(e.var(100), Some(4.0));
}

#[test]
fn c7_nesting_limits() {
    // A macro that calls itself R times deep: four levels run, a fifth is alarm 0122.
    let rec = "O9100\n#100=#100+1\nIF[#100 GE #18]GOTO9\nG65 P9100 R#18\nN9 M99";
    assert_eq!(var(&with("#100=0\nG65 P9100 R4.", rec), 100), Some(4.0));
    assert_eq!(alarm_of(&with("#100=0\nG65 P9100 R5.", rec)), 122);
    // M98 nests four deep; the fifth is alarm 0077.
    let sub = "O9200\n#100=#100+1\nIF[#100 GE #101]GOTO9\nM98 P9200\nN9 M99";
    assert_eq!(var(&with("#100=0\n#101=4\nM98 P9200", sub), 100), Some(4.0));
    assert_eq!(alarm_of(&with("#100=0\n#101=5\nM98 P9200", sub)), 77);
    // M98 is not counted among the macro levels: G65 four deep inside an M98 still runs.
    assert_eq!(
        var(
            &with(
                "#100=0\nM98 P300",
                &format!("O300\nG65 P9100 R4.\nM99\n{rec}")
            ),
            100
        ),
        Some(4.0)
    );
}

#[test]
fn c8_m98_repeat_counts() {
    let sub = "O100\n#100=#100+1\nM99";
    assert_eq!(var(&with("#100=0\nM98 P100 L3", sub), 100), Some(3.0));
    assert_eq!(var(&with("#100=0\nM98 P30100", sub), 100), Some(3.0));
    let sub1000 = "O1000\n#100=#100+1\nM99";
    assert_eq!(var(&with("#100=0\nM98 P00051000", sub1000), 100), Some(5.0));
    assert_eq!(var(&with("#100=0\nM98 P51000", sub1000), 100), Some(5.0));
    assert_eq!(var(&with("#100=0\nM98 P100", sub), 100), Some(1.0));
    // A missing program: a compile warning, alarm 0076 when the call runs.
    assert_eq!(alarm_of(&with("M98 P4444", "")), 76);
}

#[test]
fn c9_m99_forms() {
    // M99 P50 returns to N50 of the caller, skipping the blocks between.
    let e = ok(&with("M98 P100\n#100=1\nN50 #101=2", "O100\nM99 P50"));
    assert_eq!([e.var(100), e.var(101)], [None, Some(2.0)]);
    // M99 at the end of a main program starts it again (commons keep counting, locals are vacant).
    let e = ok("#100=#100+1\nIF[#100 GE 3]GOTO9\nG0 X#100\nM99\nN9 M30");
    assert_eq!(e.body(), vec!["G0 X1.", "G0 X2.", "N9 M30"]);
    // …bounded by the step limit when it never ends.
    let small = RunOptions {
        limits: fmsvm_vm::Limits {
            max_steps: 1000,
            max_blocks: 1000,
            ..Default::default()
        },
        ..RunOptions::default()
    };
    match expand_full(
        "G0 X1\nM99",
        &[],
        literal::Options::default(),
        small,
        Options::default(),
    ) {
        Err(Failure::Limit(m)) => assert!(m.contains("steps") || m.contains("blocks"), "{m}"),
        other => panic!("expected a limit, got {:?}", other.map(|e| e.text)),
    }
    // With main_m99_ends the flat program keeps the M99 for the control to repeat.
    let run = RunOptions {
        main_m99_ends: true,
        ..RunOptions::default()
    };
    let e = expand_full(
        "G0 X1\nM99",
        &[],
        literal::Options::default(),
        run,
        Options::default(),
    )
    .expect("runs");
    assert_eq!(e.body(), vec!["G0 X1.", "M99"]);
}

#[test]
fn call_blocks_with_nc_words() {
    // The NC words of an M98 or M99 block run first; call words never reach the output.
    let e = ok(&with("G0 X10 M98 P100\nG0 X30", "O100\nG1 X20 M99"));
    assert_eq!(e.body(), vec!["G0 X10.", "G1 X20.", "G0 X30.", "M30"]);
}

#[test]
fn c12_g66_calls_after_each_move_block() {
    // The row's test: O9100 runs after X10. and X20., not after M8, #1=1 or X30.
    let src = with(
        "G66 P9100 R5.\nG0 X10.\nM8\n#1=1\nX20.\nG67\nX30.",
        "O9100\n#100=#100+1\nG1 Z-#18\nM99",
    );
    let e = ok(&src);
    assert_eq!(e.var(100), Some(2.0));
    assert_eq!(
        e.body(),
        vec!["G0 X10.", "G1 Z-5.", "M8", "X20.", "G1 Z-5.", "X30.", "M30"]
    );
}

#[test]
fn m97_local_subprogram_option() {
    let src = "#100=0\nM97 P500 L2\nG0 X#100\nM30\nN500 #100=#100+1\nM99";
    let o = Options {
        syntax: fmsvm_compiler::Syntax {
            m97: true,
            ..fmsvm_compiler::Syntax::FANUC
        },
        ..Options::default()
    };
    let e = expand_full(
        src,
        &[],
        literal::Options::default(),
        RunOptions::default(),
        o,
    )
    .expect("runs");
    assert_eq!(e.body(), vec!["G0 X2.", "M30"]);
}

#[test]
fn library_programs_are_found() {
    let lib = [(
        "O9010.nc",
        "%\nO9010 (BOLT HOLE)\n#100=#24*2\nG0 X#100\nM99\n%\n",
    )];
    let e = expand_full(
        "G65 P9010 X21.",
        &lib,
        literal::Options::default(),
        RunOptions::default(),
        Options::default(),
    )
    .expect("runs");
    assert_eq!(e.body(), vec!["G0 X42."]);
}

#[test]
fn o1_o3_dprnt_formats() {
    // The rule table's example; its copy collapsed the spaces (O3): fmsvm prints the whole part in a field
    // of a places with a sign place before the digits.
    let e = ok("POPEN\n#1=1.5436\nDPRNT[X#1[44]*Z#1[03]*T#1[40]]\nDPRNT[]\nPCLOS");
    assert_eq!(e.printed, b"\x12X    1.5436 Z 1.544 T    1\n\n\x14");
    let e = ok("POPEN\n#1=-12.3456\n#2=#0\nDPRNT[A#1[53]B#2[21]C#1[10]]\nPCLOS");
    assert_eq!(e.printed, b"\x12A   -12.346B  0.0C-12\n\x14");
    // DPRNT without POPEN stops (an option allows it).
    assert!(matches!(expand("DPRNT[X#1[44]]"), Err(Failure::Alarm(..))));
    let run = RunOptions {
        print_without_popen: true,
        ..RunOptions::default()
    };
    let e = expand_full(
        "DPRNT[OK]",
        &[],
        literal::Options::default(),
        run,
        Options::default(),
    )
    .expect("runs");
    assert_eq!(e.printed, b"OK\n");
    // [54] has nine digits: a compile error.
    assert!(matches!(
        expand("POPEN\nDPRNT[X#1[54]]"),
        Err(Failure::Compile(_))
    ));
}

#[test]
fn o2_o4_bprnt_records() {
    let e = ok(
        "POPEN\n#120=258.647673\n#110=318.49362\n#112=23.9\nBPRNT[C#120[3]*#110[3]#112[0]#1[3]]\nPCLOS",
    );
    let mut want = vec![
        0x12, 0xC3, 0x00, 0x03, 0xF2, 0x58, 0xA0, 0x00, 0x04, 0xDC, 0x1E,
    ];
    want.extend_from_slice(&[0x00, 0x00, 0x00, 0x18, 0x00, 0x00, 0x00, 0x00, 0x0A, 0x14]);
    assert_eq!(e.printed, want);
}

#[test]
fn s1_message_stop_3006() {
    let e = ok("G0 X1\n#3006=1(CHECK INSERT)\nG0 X2");
    assert_eq!(
        e.body(),
        vec!["G0 X1.", "M0 (MESSAGE 1: CHECK INSERT)", "G0 X2."]
    );
}

#[test]
fn s2_timers_follow_the_estimated_machining_time() {
    // 100 mm at F1000 = 6 s; a rapid of 100 mm at 10 m/min = 0.6 s; G4 P500 = 0.5 s.
    // From X0 (the program positions X first: the time of a first positioning is not known).
    assert_eq!(
        var("G0 X0\n#3001=0\nG1 X100 F1000\n#100=#3001", 100),
        Some(6000.0)
    );
    assert_eq!(var("G0 X0\n#3001=0\nG0 X100\n#100=#3001", 100), Some(600.0));
    assert_eq!(var("#3001=0\nG4 P500\n#100=#3001", 100), Some(500.0));
    // A full circle of R10 (I-10) at F628.3185 takes 6 s.
    let v = var(
        "G1 X10 Y0 F1000\n#3001=0\nG2 I-10 F628.3185307\n#100=#3001",
        100,
    )
    .unwrap();
    assert!((v - 6000.0).abs() <= 1.0, "{v}");
    // #3001 can be reset to a value; #3002 counts hours.
    assert_eq!(
        var("G0 X0\n#3001=1000\nG1 X100 F1000\n#100=#3001", 100),
        Some(7000.0)
    );
    assert_eq!(
        var("G0 X0\n#3002=0\nG1 X6000 F1000\n#100=#3002*60", 100),
        Some(6.0)
    );
}

#[test]
fn s7_flags_3003_3004_are_accepted() {
    assert_eq!(var("#3004=3\n#100=#3004", 100), Some(3.0));
    assert_eq!(alarm_of("#3004=9"), 115);
}

fn haas(src: &str) -> Result<common::Expansion, Failure> {
    let o = Options {
        syntax: fmsvm_compiler::Syntax::HAAS,
        ..Options::default()
    };
    let run = RunOptions {
        print_without_popen: true,
        ..RunOptions::default()
    };
    expand_full(src, &[], literal::Options::default(), run, o)
}

#[test]
fn l2_c9_o5_haas_dialect() {
    // L2: IF without THEN is Haas syntax; Fanuc mode rejects it (0125).
    let src = "#1=2\n#100=0\nIF[#1 EQ 2] #100=7";
    assert!(matches!(expand(src), Err(Failure::Compile(_))));
    assert_eq!(haas(src).expect("runs").var(100), Some(7.0));
    // C9: Haas M99 Pn in a subprogram branches to Nn of the subprogram and does not return there.
    let prog = with(
        "#100=0\nM98 P200\nG0 X#100",
        "O200\n#100=#100+1\nIF[#100 GE 3]GOTO9\nM99 P5\nN9 M99\nO300\nM99",
    );
    let prog = prog.replace("O200\n#100=#100+1", "O200\nN5 #100=#100+1");
    assert_eq!(haas(&prog).expect("runs").body(), vec!["G0 X3.", "M30"]);
    // O5: DPRNT works without POPEN on Haas.
    assert_eq!(
        haas("#1=1.5\nDPRNT[X#1[11]]").expect("runs").printed,
        b"X 1.5\n"
    );
}

#[test]
fn e9_haas_comparisons_are_values() {
    // Fanuc rejects a stored comparison (0114); Haas stores 1 or 0 and branches on values.
    assert!(matches!(expand("#100=[1 LT 2]"), Err(Failure::Compile(_))));
    let e = haas(
        "#100=[1 LT 2]\n#101=[3 LT 2]+5\n#1=0\nIF[#1]GOTO5\n#102=1\nN5 IF[#9]GOTO6\n#103=1\nN6 M30",
    )
    .expect("runs");
    assert_eq!(
        [100, 101, 102, 103].map(|n| e.var(n)),
        [Some(1.0), Some(5.0), Some(1.0), Some(1.0)]
    );
    // Haas combines bracketed comparisons with AND (E9's example).
    let e = haas("#7=5\nIF[[#7 NE #0] AND [#7 GE 0] AND [#7 LE 9]]GOTO99\n#100=1\nN99 M30")
        .expect("runs");
    assert_eq!(e.var(100), None);
}

/// C2: in a call block every argument letter is a value and takes a sign — M is #13, S #19, T #20
/// (M was refused with alarm 0006 before, as if it were an M code); G, N, O still take none.
#[test]
fn c2_every_argument_letter_takes_a_sign() {
    let sub = "O9001\n#100=#13\n#101=#19\n#102=#20\nM99";
    let e = ok(&with("G65 P9001 M-1.5 S-2. T-1.5", sub));
    assert_eq!(
        [e.var(100), e.var(101), e.var(102)],
        [Some(-1.5), Some(-2.0), Some(-1.5)]
    );
    let e = ok(&with("#5=2.5\nG65 P9001 M-#5", sub));
    assert_eq!(e.var(100), Some(-2.5));
    let e = ok(&with("G66 P9001 M-3.\nG0 X1.\nG67", sub));
    assert_eq!(e.var(100), Some(-3.0));
    // Outside a call M is a code: a sign is still refused at compile time.
    assert_eq!(
        expand(&with("M-3", sub)).err().and_then(|f| f.alarm()),
        Some(6)
    );
}

/// Calls by codes the parameters bind (Fanuc 0i "macro call using a G code / an M code, subprogram call
/// using an M code / a T code"): G100 → O9010 as G65 (arguments), M123 → O9020 as a macro, M6 → O9001
/// as M98, T → O9000 with T in #149. Inside the called program the code is an ordinary code.
#[test]
fn calls_by_g_m_and_t_codes() {
    let calls = fmsvm_compiler::CodeCalls {
        g_macro: [
            Some(fmsvm_block::Code::from_tenths(1000)),
            None,
            None,
            None,
            None,
            None,
            None,
            None,
            None,
            None,
        ],
        m_macro: [
            Some(123),
            None,
            None,
            None,
            None,
            None,
            None,
            None,
            None,
            None,
        ],
        m_sub: [Some(6), None, None, None, None, None, None, None, None],
        t_sub: true,
        ..fmsvm_compiler::CodeCalls::default()
    };
    let options = fmsvm_compiler::Options {
        calls,
        ..fmsvm_compiler::Options::default()
    };
    let lib = [
        (
            "O9010.nc",
            "O9010\n#100=#24\n#101=#25\nG1 X#24 Y#25 F100.\nM99\n",
        ),
        ("O9020.nc", "O9020\n#102=#1\nM99\n"),
        ("O9001.nc", "O9001\n#103=#103+1\nM6\nM99\n"),
        ("O9000.nc", "O9000\n#104=#149\nT#149\nM99\n"),
    ];
    let src = "%\nO1\nT7\nM6\nG100 X10. Y20.\nM123 A5.\nM6\nM30\n%\n";
    let e = expand_full(
        src,
        &lib,
        common::Setup::default(),
        RunOptions::default(),
        options.clone(),
    )
    .expect("runs");
    assert_eq!(
        [e.var(100), e.var(101), e.var(102), e.var(103), e.var(104)],
        [Some(10.0), Some(20.0), Some(5.0), Some(2.0), Some(7.0)]
    );
    // The flat program: T7 from O9000, M6 from O9001 (an ordinary M6 there), the G100 macro's move.
    assert_eq!(e.body(), ["T7", "M6", "G1 X10. Y20. F100.", "M6", "M30"]);
    // Inside O9010, G100 is an ordinary G code: alarm 0010 (no such G code), not a recursive call.
    let lib2 = [("O9010.nc", "O9010\nG100 X1.\nM99\n")];
    match expand_full(
        "%\nO1\nG100 X1.\nM30\n%\n",
        &lib2,
        common::Setup::default(),
        RunOptions::default(),
        options,
    ) {
        Err(Failure::Alarm(10, _, _)) => {}
        Err(f) => panic!("{f:?}"),
        Ok(e) => panic!("ran: {}", e.text),
    }
}

/// G66.1, the each-block modal call: the G66.1 block calls the macro with its arguments, then every NC
/// block of the caller calls it with the block's own words as arguments (its motion does not run), a
/// block without motion (F100.) as well as one with; G67 ends it. Macro statements are no blocks.
#[test]
fn g66_1_calls_at_every_block() {
    let sub = "O9100\n#110=#110+1\n#[120+#110]=#24\n#[130+#110]=#9\n#[140+#110]=#1\nM99";
    let e = ok(&with(
        "#110=0\nG66.1 P9100 A1.\nX5. Y6.\n#5=1\nF100.\nG67\nX9.",
        sub,
    ));
    assert_eq!(e.var(110), Some(3.0));
    assert_eq!(
        [e.var(121), e.var(141), e.var(122), e.var(123), e.var(133)],
        [None, Some(1.0), Some(5.0), None, Some(100.0)]
    );
    // Only the block after G67 reaches the flat program.
    assert_eq!(e.body(), ["X9.", "M30"]);
}

/// A call by a code counts in the nesting as the call it stands for: a G-code macro call is a macro
/// level (four allowed, the fifth alarm 0122), an M-code subprogram call a subprogram level (the fifth
/// nested alarm 0077).
#[test]
fn calls_by_codes_count_in_the_nesting() {
    let options = fmsvm_compiler::Options {
        calls: fmsvm_compiler::CodeCalls {
            g_macro: [
                Some(fmsvm_block::Code::from_tenths(1000)),
                None,
                None,
                None,
                None,
                None,
                None,
                None,
                None,
                None,
            ],
            m_sub: [Some(6), None, None, None, None, None, None, None, None],
            ..fmsvm_compiler::CodeCalls::default()
        },
        ..fmsvm_compiler::Options::default()
    };
    let run = |main: &str, lib: &[(&str, &str)]| {
        expand_full(
            &format!("%\nO1\n{main}\nM30\n%\n"),
            lib,
            common::Setup::default(),
            RunOptions::default(),
            options.clone(),
        )
    };
    // G100 (level 1) → G65 ×3 (levels 2–4): runs; one more G65 (level 5): alarm 0122.
    let four = [
        ("O9010.nc", "O9010\nG65 P9101\nM99\n"),
        ("O9101.nc", "O9101\nG65 P9102\nM99\n"),
        ("O9102.nc", "O9102\nG65 P9103\nM99\n"),
        ("O9103.nc", "O9103\n#100=4\nM99\n"),
    ];
    assert_eq!(run("G100", &four).expect("four levels").var(100), Some(4.0));
    let mut five = four;
    five[3] = ("O9103.nc", "O9103\nG65 P9104\nM99\n");
    let lib5: Vec<(&str, &str)> = five
        .iter()
        .copied()
        .chain([("O9104.nc", "O9104\n#100=5\nM99\n")])
        .collect();
    match run("G100", &lib5) {
        Err(Failure::Alarm(122, _, _)) => {}
        other => panic!("{:?}", other.map(|e| e.text)),
    }
    // M6 (subprogram level 1) → M98 ×3: runs; one more: alarm 0077.
    let subs = [
        ("O9001.nc", "O9001\nM98 P101\nM99\n"),
        ("O101.nc", "O101\nM98 P102\nM99\n"),
        ("O102.nc", "O102\nM98 P103\nM99\n"),
        ("O103.nc", "O103\n#100=4\nM99\n"),
    ];
    assert_eq!(run("M6", &subs).expect("four levels").var(100), Some(4.0));
    let mut deeper = subs;
    deeper[3] = ("O103.nc", "O103\nM98 P104\nM99\n");
    let lib: Vec<(&str, &str)> = deeper
        .iter()
        .copied()
        .chain([("O104.nc", "O104\n#100=5\nM99\n")])
        .collect();
    match run("M6", &lib) {
        Err(Failure::Alarm(77, _, _)) => {}
        other => panic!("{:?}", other.map(|e| e.text)),
    }
}

fn code_calls(calls: fmsvm_compiler::CodeCalls) -> Options {
    Options {
        calls,
        ..Options::default()
    }
}

fn run_with(src: &str, lib: &[(&str, &str)], o: &Options) -> Result<common::Expansion, Failure> {
    expand_full(
        src,
        lib,
        common::Setup::default(),
        RunOptions::default(),
        o.clone(),
    )
}

/// S and the second auxiliary function as subprogram calls (docs/params.md "Calls by codes"): an S
/// code calls O9029 with the S value in #147, a B code O9028 with the B value in #146, as M98 does
/// (the block's other words first, locals shared, L repeats). Inside the called program the code is
/// an ordinary S or B word that reaches the flat program; O9028/O9029 come from the library.
#[test]
fn calls_by_s_and_b_codes() {
    let o = code_calls(fmsvm_compiler::CodeCalls {
        s_sub: true,
        b_sub: Some(fmsvm_block::Letter::B),
        ..fmsvm_compiler::CodeCalls::default()
    });
    let lib = [
        (
            "O9029.nc",
            "O9029 (SPINDLE)\n#100=#147\n#102=#102+1\nS#147\nM99\n",
        ),
        (
            "O9028.nc",
            "O9028 (TABLE)\n#101=#146\n#103=#1\nB#146\nM99\n",
        ),
    ];
    let src = "%\nO1\n#1=7\n#102=0\nG0 X10. S1200 M3\nB90.\nM30\n%\n";
    let e = run_with(src, &lib, &o).expect("runs");
    assert_eq!(
        [e.var(100), e.var(101), e.var(102), e.var(103)],
        [Some(1200.0), Some(90.0), Some(1.0), Some(7.0)]
    );
    // The block's other words run first; the S and B inside the called programs are ordinary words.
    assert_eq!(e.body(), ["G0 X10. M3", "S1200", "B90.", "M30"]);
    // L repeats the subprogram, as M98 L does.
    let e = run_with("%\nO1\n#102=0\nS500 L3\nM30\n%\n", &lib, &o).expect("runs");
    assert_eq!(e.var(102), Some(3.0));
    assert_eq!(e.body(), ["S500", "S500", "S500", "M30"]);
    // A computed S value goes to #147 as computed.
    let e = run_with("%\nO1\n#5=40\nS[#5*25]\nM30\n%\n", &lib, &o).expect("runs");
    assert_eq!(e.var(100), Some(1000.0));
    // Without the parameters S and B are ordinary words (B the rotary axis).
    let e = run_with(src, &lib, &Options::default()).expect("runs");
    assert_eq!(e.body(), ["G0 X10. S1200 M3", "B90.", "M30"]);
    assert_eq!(e.var(100), None);
    // A missing O9029: a compile warning, alarm 0076 when the S block runs.
    match run_with(src, &lib[1..], &o) {
        Err(Failure::Alarm(76, _, _)) => {}
        other => panic!("{:?}", other.map(|e| e.text)),
    }
}

/// The second auxiliary function moved off B (Fanuc parameter 3460: here U): U calls O9028 and B is
/// the rotary axis again.
#[test]
fn the_second_auxiliary_function_on_another_address() {
    let o = code_calls(fmsvm_compiler::CodeCalls {
        b_sub: Some(fmsvm_block::Letter::U),
        ..fmsvm_compiler::CodeCalls::default()
    });
    let lib = [("O9028.nc", "O9028\n#101=#146\nM99\n")];
    let e = run_with("%\nO1\nG0 B45. U12.5\nM30\n%\n", &lib, &o).expect("runs");
    assert_eq!(e.var(101), Some(12.5));
    assert_eq!(e.body(), ["G0 B45.", "M30"]);
}

/// The common-variable ranges as a parameter (macro-b-rules V4): a number outside them is 0115, at
/// compile time when written directly, when the indirect reference runs otherwise; the default is
/// #100–#199 and #500–#999.
#[test]
fn v4_common_ranges_follow_the_parameters() {
    let yaskawa = Options {
        commons: fmsvm_compiler::ir::CommonRanges {
            volatile: Some((100, 149)),
            retained: Some((500, 549)),
        },
        ..Options::default()
    };
    let e = run_with("#149=1\n#549=2\n#[148+1]=3", &[], &yaskawa).expect("runs");
    assert_eq!([e.var(149), e.var(549)], [Some(3.0), Some(2.0)]);
    for src in ["#150=1", "#100=#550", "G0 X#199"] {
        match run_with(src, &[], &yaskawa) {
            Err(f) => assert_eq!(f.alarm(), Some(115), "{src}"),
            Ok(e) => panic!("{src} ran: {}", e.text),
        }
    }
    match run_with("#1=150\n#[#1]=1", &[], &yaskawa) {
        Err(Failure::Alarm(115, m, 2)) => assert!(m.contains("#100–#149 and #500–#549"), "{m}"),
        other => panic!("{:?}", other.map(|e| e.text)),
    }
    // The 30i-style extension #100–#499 makes #300 a (volatile) common.
    let wide = Options {
        commons: fmsvm_compiler::ir::CommonRanges {
            volatile: Some((100, 499)),
            retained: Some((500, 999)),
        },
        ..Options::default()
    };
    assert_eq!(alarm_of("#300=1"), 115);
    assert_eq!(
        run_with("#300=4\n#[301]=5", &[], &wide)
            .expect("runs")
            .var(301),
        Some(5.0)
    );
}
