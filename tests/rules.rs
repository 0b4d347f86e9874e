//! One test per row of `shared/reference/macro-b-rules.md` that the language core covers, named by row
//! id. Every expected value is worked out by hand from the rule (the row's own examples where it has
//! them). Rows of later work (calls C1–C12, V3, V12; DPRNT O1–O5; timers S2, S7) are not here.

use crate::common;

use common::{Failure, alarm_of, assert_value, expand, expand_with, ok, value};
use fmsvm_canon::decode::DecimalInput;
use fmsvm_compiler::Options;
use fmsvm_emit::literal;
use fmsvm_vm::Limits;

fn body(src: &str) -> Vec<String> {
    ok(src).body().into_iter().map(str::to_string).collect()
}

fn compile_alarms(src: &str) -> Vec<u32> {
    match expand(src) {
        Err(Failure::Compile(d)) => d
            .iter()
            .filter(|d| d.is_error())
            .filter_map(|d| d.alarm)
            .collect(),
        Ok(_) => vec![],
        Err(f) => panic!("{src:?}: expected a compile error, got {f:?}"),
    }
}

#[test]
fn v1_hash0_is_vacant_and_cannot_be_assigned() {
    assert_eq!(value("#100=#0"), None);
    assert_eq!(compile_alarms("#0=1"), vec![116]);
    assert_eq!(alarm_of("#1=0\n#[#1]=5"), 116);
}

#[test]
fn v2_locals_start_vacant() {
    assert_value("IF[#1 EQ #0]THEN #100=1", 1.0);
    assert_eq!(value("#100=#33"), None);
}

#[test]
fn v4_s6_common_ranges() {
    assert_value("#150=2\n#999=3\n#100=#150+#999", 5.0);
    assert_eq!(compile_alarms("#200=1"), vec![115]);
    assert_eq!(compile_alarms("#34=1"), vec![115]);
    assert_eq!(compile_alarms("#100=#499"), vec![115]);
    // A run starts with #100–#199 vacant.
    assert_eq!(value("#101=1"), None);
}

#[test]
fn v5_vacant_in_arithmetic_is_zero_but_copy_keeps_it() {
    assert_value("#100=#0+1", 1.0);
    assert_value("#100=#0*10", 0.0);
    assert_value("#100=#0+#0", 0.0);
    assert_eq!(value("#100=#1"), None);
}

#[test]
fn v6_vacant_word_is_omitted_zero_is_not() {
    assert_eq!(body("G90 X20 Y#1"), vec!["G90 X20."]);
    assert_eq!(body("#1=0\nG90 X20 Y#1"), vec!["G90 X20. Y0."]);
    // A negated vacant variable stays vacant in an address (E8: the sign belongs to the word).
    assert_eq!(body("G1 X-#1 Y1"), vec!["G1 Y1."]);
}

#[test]
fn v7_comparisons_with_vacant() {
    let truth = |cond: &str| value(&format!("IF[{cond}]THEN #100=1")).is_some();
    assert!(truth("#1 EQ #0"));
    assert!(!truth("0 EQ #0"));
    assert!(truth("#1 NE 0"));
    assert!(!truth("#1 GT 0"));
    assert!(truth("0 GE #0"));
    assert!(truth("#1 LE 0"));
    assert!(!truth("#1 LT 0"));
}

#[test]
fn v8_ieee_double_accumulation() {
    // Adding 0.1 3600 times passes 360 by ~1.3e-11 in IEEE double (corpus README): the loop runs 3600
    // times, not 3601.
    assert_value(
        "#1=0\n#100=0\nWHILE[#1LE360]DO1\n#1=#1+0.1\n#100=#100+1\nEND1",
        3600.0,
    );
}

#[test]
fn v10_integer_addresses_round_half_up() {
    assert_eq!(body("#1=1.23\nM#1"), vec!["M1"]);
    assert_eq!(body("#1=1.6\nM#1"), vec!["M2"]);
    assert_eq!(body("#1=3.4999999\nM#1"), vec!["M3"]);
    assert_eq!(body("#1=3.5\nM#1"), vec!["M4"]);
    assert_eq!(body("#1=1000.4999\nS#1"), vec!["S1000"]);
    assert_eq!(body("#1=1000.5\nS#1"), vec!["S1001"]);
    assert_eq!(body("D[1.67]"), vec!["D2"]);
    assert_eq!(body("M[3.0]"), vec!["M3"]);
    assert_eq!(body("S[1000.4999]"), vec!["S1000"]);
    assert_eq!(compile_alarms("M3.0"), vec![7]);
    assert_eq!(compile_alarms("S1000.0"), vec![7]);
    assert_eq!(alarm_of("#112=5630\nM#112"), 3);
    // G codes: not rounded; a value that is no G code is alarm 0010.
    assert_eq!(body("#1=54.1\nG#1"), vec!["G54.1"]);
    assert_eq!(alarm_of("#1=1.5\nG#1"), 10);
}

#[test]
fn v11_decimal_point_input() {
    assert_eq!(body("#111=123\nG0 X#111"), vec!["G0 X123."]);
    let inc = |src: &str| {
        let o = common::Setup {
            rules: fmsvm_canon::decode::InputRules {
                decimal: DecimalInput::Increment,
                ..Default::default()
            },
            ..Default::default()
        };
        expand_with(src, o, Limits::default(), Options::default())
            .map(|e| e.body().into_iter().map(str::to_string).collect::<Vec<_>>())
            .expect("expands")
    };
    assert_eq!(inc("G0 X12345"), vec!["G0 X12.345"]);
    assert_eq!(inc("G0 X1"), vec!["G0 X0.001"]);
    assert_eq!(inc("G0 X123.45"), vec!["G0 X123.45"]);
    // Values from variables and expressions are in mm, and macro constants are plain numbers.
    assert_eq!(inc("#1=10\nG0 X#1 Y[10]"), vec!["G0 X10. Y10."]);
    // The calculator default: X10 = 10 mm.
    assert_eq!(body("G0 X10"), vec!["G0 X10."]);
}

#[test]
fn e1_bracket_nesting_limit_118() {
    assert_value("#100=[[[[[1]]]]]", 1.0);
    assert_eq!(compile_alarms("#100=[[[[[[1]]]]]]"), vec![118]);
    assert_eq!(compile_alarms("#100=SIN[[[[[[1]]]]]]"), vec![118]);
}

#[test]
fn e2_relational_two_letters_and_bitwise_logic() {
    assert_eq!(compile_alarms("IF[#1 LTE 2]GOTO1\nN1"), vec![114]);
    assert_value("#100=1 OR 2", 3.0);
    assert_value("#100=27 MOD 20", 7.0);
}

#[test]
fn e3_round_in_assignment_and_in_address() {
    assert_value("#100=ROUND[3.54]", 4.0);
    // Inch: ROUND inside an address rounds to 0.0001 before the sum.
    assert_eq!(
        body("G20\n#1=1.00333\nG0 X[ROUND[#1]+ROUND[#1]]"),
        vec!["G20", "G0 X2.0066"]
    );
    assert_eq!(
        body("G20\n#1=1.00333\nG0 X[#1+#1]"),
        vec!["G20", "G0 X2.0067"]
    );
    // Metric: 0.001 mm.
    assert_eq!(
        body("#1=1.00333\nG0 X[ROUND[#1]+ROUND[#1]]"),
        vec!["G0 X2.006"]
    );
    assert_eq!(body("#1=1.00333\nG0 X[#1+#1]"), vec!["G0 X2.007"]);
}

#[test]
fn e4_fix_truncates_fup_rounds_away_from_zero() {
    assert_value("#100=FIX[-1.2]", -1.0);
    assert_value("#100=FUP[-1.2]", -2.0);
    assert_value("#100=FUP[-3.1]", -4.0);
    assert_value("#100=FIX[1.7]", 1.0);
    assert_value("#100=FUP[1.2]", 2.0);
    assert_value("#100=FUP[2]", 2.0);
}

#[test]
fn e5_degrees_and_two_argument_atan() {
    assert_value("#100=SIN[90]", 1.0);
    assert_value("#100=COS[180]", -1.0);
    assert_value("#100=TAN[45]", 1.0);
    assert_value("#100=ATAN[1]/[1]", 45.0);
    assert_value("#100=ATAN[1,1]", 45.0);
    // The textbook's unbracketed argument.
    assert_value("#1=30\n#100=SIN#1", 0.5);
}

#[test]
fn e7_precedence() {
    assert_value("#100=12/4*3", 9.0);
    assert_value("#100=12-4+3", 11.0);
    assert_value("#100=12+2/2", 13.0);
    assert_value("#100=[12+2]/2", 7.0);
    assert_value("#100=2+3 AND 1", 3.0);
    assert_value("#100=4 OR 1 AND 2", 4.0);
}

#[test]
fn e8_unary_signs() {
    assert_value("#1=3\n#100=-#1", -3.0);
    assert_eq!(body("#1=3\nG1 X-#1"), vec!["G1 X-3."]);
    assert_value("#100=-[2+3]", -5.0);
    assert_value("#1=3\n#100=2*-#1", -6.0);
    assert_value("#100=+1.23", 1.23);
    assert_value("#100=-[COS[30]]", -(3f64.sqrt() / 2.0));
    assert_eq!(compile_alarms("N-10 G0 X1"), vec![6]);
    assert_eq!(compile_alarms("M-3"), vec![6]);
}

#[test]
fn e9_comparison_is_not_a_value() {
    assert_eq!(compile_alarms("#2=[1 LT 2]"), vec![114]);
    assert_eq!(compile_alarms("#2=1 LT 2"), vec![114]);
    // Bracketed comparisons combined with AND in a condition (Haas form) are accepted.
    assert_value(
        "#7=5\nIF[[#7 NE #0] AND [#7 GE 0] AND [#7 LE 9]]THEN #100=1",
        1.0,
    );
}

#[test]
fn e10_inverse_trig_quadrants() {
    assert_value("#100=ATAN[1]/[-1]", 135.0);
    assert_value("#100=ATAN[-1]/[-1]", 225.0);
    assert_value("#100=ATAN[-1]/[1]", 315.0);
    assert_value("#100=ATAN[0]/[-1]", 180.0);
    assert_value("#100=ASIN[-0.5]", 330.0);
    assert_value("#100=ACOS[-1]", 180.0);
    assert_value("#100=ACOS[0.5]", 60.0);
}

#[test]
fn e11_domain_errors_and_overflow() {
    assert_eq!(alarm_of("#1=SQRT[-4]"), 119);
    assert_value("#100=SQRT[#0]", 0.0);
    assert_eq!(alarm_of("#1=LN[0]"), 119);
    assert_eq!(alarm_of("#1=ASIN[2]"), 119);
    assert_eq!(alarm_of("#1=EXP[1000]"), 111);
    assert_eq!(alarm_of("#1=99999999999 AND 1"), 110);
    // NaN or infinity never reaches a coordinate.
    assert_eq!(alarm_of("#1=EXP[709]*EXP[709]"), 111);
}

#[test]
fn e12_round_half_away_from_zero() {
    for (x, r) in [
        (1.5, 2.0),
        (-1.5, -2.0),
        (2.5, 3.0),
        (0.5, 1.0),
        (0.00001, 0.0),
        (0.99999, 1.0),
        (3.54, 4.0),
    ] {
        assert_value(&format!("#100=ROUND[{x}]"), r);
    }
    assert_eq!(
        body("#101=27/32\nG91 G00 X[ROUND[#101]]"),
        vec!["G91 G0 X0.844"]
    );
    assert_eq!(
        body("G20\n#101=27/32\nG91 G00 X[ROUND[#101]]"),
        vec!["G20", "G91 G0 X0.8438"]
    );
    assert_value("#100=ROUND[27/32]", 1.0);
}

#[test]
fn e13_mod_logic_bcd() {
    assert_value("#100=27 MOD 20", 7.0);
    assert_value("#100=5 AND 3", 1.0);
    assert_value("#100=5 XOR 3", 6.0);
    assert_value("#100=1.7 OR 2", 3.0);
    assert_value("#100=BCD[12]", 18.0);
    assert_value("#100=BIN[18]", 12.0);
    assert_value("#100=ADP[1]", 1.0);
    assert_value("#100=POW[2,3]", 8.0);
    assert_value("#100=EXP[0]+LN[1]", 1.0);
    assert_value("#100=ABS[-2.5]", 2.5);
}

#[test]
fn a3_zero_divide_only_when_executed() {
    assert_eq!(alarm_of("#1=5/0"), 112);
    assert_eq!(alarm_of("#1=5/#0"), 112);
    assert_eq!(alarm_of("#1=5 MOD 0"), 112);
    assert_value("#100=ATAN[1]/[0]", 90.0);
    assert_value("#100=1\nIF[1 EQ 2]THEN #100=5/0", 1.0);
}

#[test]
fn l1_loops_and_branches() {
    // WHILE..DO..END, nested, with IF..GOTO forward and GOTO to the END line (the hemisphere's shape).
    assert_value(
        "#100=0\n#1=0\nWHILE[#1 LT 3]DO1\n#2=0\nWHILE[#2 LT 4]DO2\n#100=#100+1\n#2=#2+1\nEND2\n#1=#1+1\nIF[#1 GE 2]GOTO9\nN9 END1",
        12.0,
    );
    // DOm without WHILE loops until a GOTO leaves it.
    assert_value(
        "#100=0\nDO1\n#100=#100+1\nIF[#100 GE 5]GOTO20\nEND1\nN20 M30",
        5.0,
    );
    // Computed GOTO.
    assert_value(
        "#5=30\nGOTO#5\nN10 #100=1\nGOTO99\nN30 #100=3\nN99 M30",
        3.0,
    );
    // GOTO backwards as a loop.
    assert_value("#100=0\nN5 #100=#100+1\nIF[#100 LT 7]GOTO5", 7.0);
}

#[test]
fn l3_missing_target_warns_and_alarms_only_when_taken() {
    let e = ok("#1=1\nIF[#1 EQ 2]GOTO777\n#100=4");
    assert_eq!(e.var(100), Some(4.0));
    assert!(
        e.warnings
            .iter()
            .any(|w| !w.is_error() && w.alarm == Some(128))
    );
    assert_eq!(alarm_of("#1=2\nIF[#1 EQ 2]GOTO777\n#100=4"), 128);
    // A jump into a DO range from outside: a warning, alarm 128 when taken.
    let src = "#1=1\nIF[#1 EQ 2]GOTO5\nWHILE[#1 LT 3]DO1\nN5 #1=#1+1\nEND1\n#100=#1";
    assert_eq!(ok(src).var(100), Some(3.0));
    assert_eq!(alarm_of(&src.replace("#1=1\nIF", "#1=2\nIF")), 128);
}

#[test]
fn l4_reading_ends_at_the_closing_percent() {
    let e = ok("%\nO1\nG0 X1\nM30\n%\nTHIS IS NOT A PROGRAM ]]] #0=1\nGOTO99\n");
    assert_eq!(e.body(), vec!["G0 X1.", "M30"]);
}

#[test]
fn l5_computed_goto_rounds_and_checks_range() {
    let prog = |v: &str| format!("#1={v}\nGOTO#1\nN4 #100=4\nGOTO9\nN5 #100=5\nN9 M30");
    assert_value(&prog("4.49"), 4.0);
    assert_value(&prog("4.5"), 5.0);
    assert_eq!(alarm_of(&prog("0")), 128);
    assert_eq!(alarm_of(&prog("-4")), 128);
    assert_eq!(alarm_of(&prog("100000")), 128);
    assert_eq!(alarm_of(&prog("6")), 128);
}

#[test]
fn l6_if_then_takes_one_assignment() {
    assert_value("#1=2\n#100=0\nIF[#1 EQ 2]THEN #100=#100+1", 1.0);
    assert_eq!(compile_alarms("IF[#1 EQ 2]THEN G00 X5.0"), vec![125]);
    // IF..GOTO falls through when false.
    assert_value("#100=1\nIF[1 EQ 2]GOTO5\n#100=2\nN5 M30", 2.0);
}

#[test]
fn l7_do_end_rules() {
    assert_eq!(compile_alarms("WHILE[#1 LT 3]DO4\nEND4"), vec![126, 126]);
    assert_eq!(compile_alarms("WHILE[#1 LT 3]DO1\n#1=#1+1"), vec![124]);
    assert_eq!(compile_alarms("DO1\nDO2\nEND1\nEND2"), vec![126, 126]);
    assert_value(
        "#100=0\nDO1\n#100=#100+1\nIF[#100 GE 2]GOTO5\nEND1\nN5 DO1\n#100=#100+10\nIF[#100 GE 30]GOTO6\nEND1\nN6 M30",
        32.0,
    );
    // A GOTO out of a range is allowed.
    assert_value(
        "#100=0\nWHILE[1 EQ 1]DO1\n#100=#100+1\nGOTO8\nEND1\nN8 M30",
        1.0,
    );
}

#[test]
fn s1_macro_alarm_3000() {
    match expand("G0 X1\n#3000=7(TOOL BROKEN)\nG0 X2") {
        Err(Failure::Alarm(n, msg, line)) => {
            assert_eq!(n, 3007);
            assert_eq!(msg, "TOOL BROKEN");
            assert_eq!(line, 2);
        }
        other => panic!("expected alarm 3007, got {:?}", other.map(|e| e.text)),
    }
}

#[test]
fn s3_s8_modal_information() {
    assert_value("G91\n#100=#4003", 91.0);
    assert_value("G1 X1 F200\n#100=#4001", 1.0);
    assert_value("G1 X1 F200\n#100=#4109", 200.0);
    assert_value("#100=#4006", 21.0);
    assert_value("#100=#4014", 54.0);
    assert_value("G55 G0 X0\n#100=#4214", 55.0);
    assert_value("T12\n#100=#4120", 12.0);
}

#[test]
fn s4_s9_positions() {
    assert_value("G90 G0 X10 Y20\n#100=#5001+#5002", 30.0);
    assert_value("G90 G0 X10\nG91 X5\n#100=#5041", 15.0);
    // Dwell words are not an end point.
    assert_value("G90 G0 X10\nG4 X2.\n#100=#5001", 10.0);
    assert_eq!(alarm_of("#5001=3"), 116);
}

#[test]
fn s5_work_offsets() {
    assert_value("#5221=100\n#100=#5221", 100.0);
    // Machine position = work position + G54 offset.
    assert_value("#5221=100\nG54 G90 G0 X10\n#100=#5021", 110.0);
    assert_value("#1=1\n#[#1*20+5201]=7\n#100=#5221", 7.0);
}

#[test]
fn literal_output_format() {
    // Trailing zeros trimmed, never -0., integer addresses without a point.
    assert_eq!(
        body("#1=-0.0001\nG1 X#1 Y10.500 Z-0.25 F100 S800 T1"),
        vec!["G1 X0. Y10.5 Z-0.25 F100. S800 T1"]
    );
    // Macro statements produce no line; N words are kept; comments only on request.
    assert_eq!(
        body("N10 #1=5\nN20 G0 X#1 (MOVE)\n(ALONE)"),
        vec!["N20 G0 X5."]
    );
}

#[test]
fn syntax_as_controls_read_it() {
    // No spaces, lower case, CR LF, `;` as end of block, `:` program number, words from expressions.
    let e = ok(
        "%\r\n:0042\r\n#1=3;#2=4\r\ng1x#1y-#2\r\n#10=2\r\nG#10 X[#1*COS[60]] R5 M#1\r\n#[#1+97]=5\r\n#101=#[100]+#100\r\n%\r\n",
    );
    // The arc has an R: literal output checks arcs before writing them (a G2 without a centre is
    // alarm 0020 there, as on a control).
    assert_eq!(e.text, "%\nO0042\nG1 X3. Y-4.\nG2 X1.5 R5. M3\n%\n");
    assert_eq!(e.var(101), Some(10.0));
    // Comment lines before the O number are the tape leader, not a program of their own.
    let e = ok("%\n(SHOP 4, MACHINE 7)\n(REV B)\nO1\nG0 X1\nM30\n%\n");
    assert_eq!(e.text, "%\nO0001\nG0 X1.\nM30\n%\n");
    // Several programs in one file: the first one runs.
    let e = ok("O1\nG0 X1\nM30\nO1000\nG0 X99\nM99\n");
    assert_eq!(e.body(), vec!["G0 X1.", "M30"]);
}

#[test]
fn hygiene_deep_and_long_input_is_refused_not_crashed() {
    let deep = format!("#1={}1{}", "[".repeat(10_000), "]".repeat(10_000));
    assert_eq!(compile_alarms(&deep), vec![118]);
    assert_eq!(
        compile_alarms(&format!("#1={}1", "-".repeat(10_000))),
        vec![114]
    );
    assert_eq!(
        compile_alarms(&format!("#1={}", vec!["1"; 50_000].join("+"))),
        vec![114]
    );
    // Just under the token limit, a long chain still compiles and runs (its tree is ~1000 deep).
    let chain = format!("#100={}", vec!["1"; 990].join("+"));
    assert_value(&chain, 990.0);
    // NUL and other control characters are errors, not crashes.
    assert!(matches!(expand("G1 X1\u{0}\n"), Err(Failure::Compile(_))));
    // Numbers too large for a coordinate are alarm 0003, never printed.
    assert_eq!(alarm_of("G1 X123456789"), 3);
    assert_eq!(alarm_of("#1=1000000*1000000\nG1 X#1"), 3);
}

fn with_semantics(src: &str, sem: fmsvm_vm::value::Semantics) -> Option<f64> {
    let run = fmsvm_vm::RunOptions {
        semantics: sem,
        ..fmsvm_vm::RunOptions::default()
    };
    common::expand_full(
        src,
        &[],
        literal::Options::default(),
        run,
        Options::default(),
    )
    .expect("runs")
    .var(100)
}

#[test]
fn e10_nat_option_and_e13_mod_option() {
    use fmsvm_vm::value::Semantics;
    let nat = Semantics {
        nat: true,
        ..Semantics::default()
    };
    // NAT: −180…180 for ATAN, −90…90 for ASIN.
    assert_eq!(with_semantics("#100=ATAN[-1]/[-1]", nat), Some(-135.0));
    assert_eq!(with_semantics("#100=ATAN[1]/[-1]", nat), Some(135.0));
    assert_eq!(
        with_semantics("#100=ASIN[-0.5]", nat).map(|v| (v * 1e9).round() / 1e9),
        Some(-30.0)
    );
    assert_eq!(
        with_semantics("#100=ATAN[-1]", nat).map(|v| (v * 1e9).round() / 1e9),
        Some(-45.0)
    );
    // Default: 0…360.
    assert_value("#100=ATAN[-1]", 315.0);
    // MOD: the remainder of the values (sign of the dividend), or of the rounded integers (30i rule).
    assert_value("#100=7.5 MOD 2", 1.5);
    assert_value("#100=-7 MOD 3", -1.0);
    let ints = Semantics {
        mod_integers: true,
        ..Semantics::default()
    };
    assert_eq!(with_semantics("#100=7.5 MOD 2", ints), Some(0.0));
    assert_eq!(with_semantics("#100=-7.4 MOD 3", ints), Some(-1.0));
}

#[test]
fn e7_logic_level_option() {
    use fmsvm_compiler::precedence::LogicLevel;
    let with = |src: &str, logic: LogicLevel| {
        let o = Options {
            logic,
            ..Options::default()
        };
        common::expand_full(
            src,
            &[],
            literal::Options::default(),
            fmsvm_vm::RunOptions::default(),
            o,
        )
        .expect("runs")
        .var(100)
    };
    // The row's examples: Fanuc/NCT 3 and 4; Rockwell (with + -, left to right) 1 and 0; lowest 1 and 0.
    assert_eq!(with("#100=2+3 AND 1", LogicLevel::Fanuc), Some(3.0));
    assert_eq!(with("#100=4 OR 1 AND 2", LogicLevel::Fanuc), Some(4.0));
    assert_eq!(with("#100=2+3 AND 1", LogicLevel::Additive), Some(1.0));
    assert_eq!(with("#100=4 OR 1 AND 2", LogicLevel::Additive), Some(0.0));
    assert_eq!(with("#100=2+3 AND 1", LogicLevel::Lowest), Some(1.0));
    assert_eq!(with("#100=4 OR 1 AND 2", LogicLevel::Lowest), Some(0.0));
    // Lowest: `1 OR 2+4` is 1 OR 6 = 7; additive: left to right (1 OR 2)+4 = 7 too; Fanuc: 1 OR 2 then +4 = 7.
    assert_eq!(with("#100=1 OR 2*3", LogicLevel::Lowest), Some(7.0));
    assert_eq!(with("#100=8 AND 12+1", LogicLevel::Lowest), Some(8.0));
    assert_eq!(with("#100=8 AND 12+1", LogicLevel::Additive), Some(9.0));
    assert_eq!(with("#100=8 AND 12+1", LogicLevel::Fanuc), Some(9.0));
    // Arithmetic itself is never regrouped, inside brackets and functions neither.
    for logic in [LogicLevel::Additive, LogicLevel::Lowest] {
        assert_eq!(
            with("#100=12/4*3+[12-4+3]*ABS[2+3*-2]", logic),
            Some(9.0 + 11.0 * 4.0)
        );
    }
}
