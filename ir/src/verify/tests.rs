use super::*;
use crate::span::Span;
use crate::{BinOp, BlockInfo, GotoTable, PrintInfo};

/// A valid function: `#1 = 2 + #1`, a word, an emitted block, a loop back, the end.
fn good() -> Program {
    let ops = vec![
        Op::Const { dst: 1, k: 0 },
        Op::Bin {
            op: BinOp::Add,
            dst: 35,
            a: 34,
            b: 1,
        },
        Op::Jump { target: 1 },
        Op::Word {
            letter: fmsvm_block::Letter::X,
            flags: Default::default(),
            src: 35,
        },
        Op::EmitBlock { info: 0 },
        Op::Branch {
            cond: 35,
            when: false,
            target: 1,
        },
        Op::End,
    ];
    let f = Function {
        number: Some(1),
        title: u32::MAX,
        n_slots: 36,
        slot_consts: vec![(34, 2.0)],
        consts: vec![1.0],
        literals: Vec::new(),
        spans: {
            let mut s = crate::span::OpSpans::default();
            s.resize(ops.len(), Span::default());
            s
        },
        ops,
        blocks: vec![0, 3, 6],
        goto_tables: vec![GotoTable {
            entries: vec![(10, GotoDest::Block(1)), (20, GotoDest::IntoLoop)],
        }],
        infos: vec![BlockInfo {
            file: 0,
            line: 1,
            column: 1,
            block_delete: false,
            comment: 0,
        }],
        labels: vec![(10, 1), (20, 2)],
        prints: vec![PrintInfo {
            binary: false,
            items: vec![PrintItem::Value {
                slot: 1,
                whole: 5,
                frac: 3,
            }],
        }],
    };
    Program {
        functions: vec![f],
        strings: vec!["comment".into()],
        ..Program::default()
    }
}

/// `good()` changed by `edit` must be refused with a message containing `want`.
fn refused(edit: impl FnOnce(&mut Program), want: &str) {
    let mut p = good();
    edit(&mut p);
    match verify(&p) {
        Ok(()) => panic!("accepted, wanted an error with {want:?}"),
        Err(e) => {
            let text = e.to_string();
            assert!(text.contains(want), "{text:?} does not mention {want:?}");
        }
    }
}

fn f0(p: &mut Program) -> &mut Function {
    &mut p.functions[0]
}

#[test]
fn the_valid_example_verifies() {
    assert_eq!(verify(&good()), Ok(()));
}

#[test]
fn slots_out_of_range_are_refused() {
    refused(
        |p| f0(p).ops[1] = Op::Copy { dst: 35, src: 36 },
        "slot 36 out of range (the function has 36 slots)",
    );
    refused(
        |p| {
            f0(p).ops[3] = Op::Word {
                letter: fmsvm_block::Letter::X,
                flags: Default::default(),
                src: 9999,
            }
        },
        "slot 9999 out of range",
    );
    refused(
        |p| {
            f0(p).prints[0].items[0] = PrintItem::Value {
                slot: 40,
                whole: 1,
                frac: 1,
            }
        },
        "print 0: slot 40 out of range",
    );
    refused(
        |p| f0(p).n_slots = 20,
        "20 slots: a function needs at least 34",
    );
    refused(
        |p| f0(p).slot_consts[0].0 = 36,
        "constant slot: slot 36 out of range",
    );
}

#[test]
fn writes_to_constants_and_to_slot_0_are_refused() {
    refused(
        |p| f0(p).ops[1] = Op::Copy { dst: 34, src: 1 },
        "writes constant slot 34",
    );
    refused(
        |p| f0(p).ops[0] = Op::Const { dst: 0, k: 0 },
        "writes slot 0",
    );
    refused(
        |p| f0(p).slot_consts.push((34, 3.0)),
        "constant slot 34 is given twice",
    );
    refused(
        |p| f0(p).slot_consts[0].0 = 5,
        "constant slot 5 is #0 or a local",
    );
    refused(
        |p| f0(p).slot_consts[0].1 = f64::INFINITY,
        "holds inf, not a finite value",
    );
    refused(
        |p| f0(p).consts[0] = f64::NEG_INFINITY,
        "constant pool holds -inf",
    );
}

#[test]
fn commons_constants_and_tables_out_of_range_are_refused() {
    refused(
        |p| {
            f0(p).ops[0] = Op::LoadCommon {
                dst: 1,
                index: COMMONS as u16,
            }
        },
        "common 900 out of range",
    );
    refused(
        |p| {
            f0(p).ops[0] = Op::StoreCommon {
                index: 9000,
                src: 1,
            }
        },
        "common 9000 out of range",
    );
    refused(
        |p| f0(p).ops[0] = Op::Const { dst: 1, k: 1 },
        "constant 1 out of range (there are 1)",
    );
    refused(
        |p| f0(p).ops[4] = Op::EmitBlock { info: 3 },
        "block info 3 out of range",
    );
    refused(
        |p| f0(p).ops[4] = Op::Print { print: 1 },
        "print 1 out of range",
    );
    refused(
        |p| f0(p).ops[2] = Op::Goto { src: 1, table: 1 },
        "GOTO table 1 out of range",
    );
}

#[test]
fn strings_out_of_range_are_refused() {
    refused(|p| f0(p).title = 1, "title: string 1 out of range");
    refused(
        |p| f0(p).infos[0].comment = 7,
        "block info 0 comment: string 7",
    );
    refused(
        |p| {
            f0(p).ops[6] = Op::Alarm {
                number: 128,
                message: 2,
            }
        },
        "string 2 out of range (the program has 1 strings)",
    );
    refused(
        |p| f0(p).ops[0] = Op::Message { src: 1, message: 5 },
        "string 5 out of range",
    );
    refused(
        |p| f0(p).prints[0].items.push(PrintItem::Text(4)),
        "print 0: string 4",
    );
}

#[test]
fn targets_out_of_range_are_refused() {
    refused(
        |p| f0(p).ops[2] = Op::Jump { target: 3 },
        "block 3 out of range (the function has 3 blocks)",
    );
    refused(
        |p| {
            f0(p).ops[5] = Op::Branch {
                cond: 1,
                when: true,
                target: 77,
            }
        },
        "block 77 out of range",
    );
    refused(
        |p| f0(p).goto_tables[0].entries[0].1 = GotoDest::Block(3),
        "GOTO table 0, N10: block 3 out of range",
    );
    refused(|p| f0(p).labels[1].1 = 9, "label N20: block 9 out of range");
}

#[test]
fn unsorted_tables_are_refused() {
    refused(
        |p| f0(p).goto_tables[0].entries.reverse(),
        "GOTO table 0: N20 then N10, not sorted",
    );
    refused(
        |p| f0(p).labels = vec![(10, 1), (10, 2)],
        "labels: N10 then N10",
    );
}

#[test]
fn bad_block_structure_is_refused() {
    refused(
        |p| f0(p).blocks = vec![3, 6],
        "the first block starts at Some(3)",
    );
    refused(|p| f0(p).blocks = vec![], "the first block starts at None");
    refused(|p| f0(p).blocks = vec![0, 6, 3], "block 2 starts at op 3");
    refused(
        |p| f0(p).blocks = vec![0, 3, 7],
        "block 2 starts at op 7, past the 7 ops",
    );
    refused(
        |p| f0(p).blocks = vec![0, 2, 6],
        "block 0 does not end with a terminator",
    );
    refused(
        |p| f0(p).blocks = vec![0, 6],
        "Jump { target: 1 } ends block 0 before its end",
    );
    refused(
        |p| {
            let f = f0(p);
            f.ops.pop();
            f.spans.pop();
            f.blocks = vec![0, 3];
            f.labels.pop();
        },
        "in the last block has no next block",
    );
    refused(
        |p| {
            f0(p).ops.clear();
            f0(p).spans.clear();
        },
        "the function has no ops",
    );
    refused(
        |p| {
            f0(p).spans.pop();
        },
        "6 spans for 7 ops",
    );
    refused(|p| p.functions.clear(), "the program has no function");
}

#[test]
fn bad_arity_and_print_digits_are_refused() {
    refused(
        |p| {
            f0(p).ops[1] = Op::Func1 {
                f: Func::Pow,
                dst: 35,
                a: 1,
            }
        },
        "POW takes two arguments",
    );
    refused(
        |p| {
            f0(p).ops[1] = Op::Func2 {
                f: Func::Sin,
                dst: 35,
                a: 1,
                b: 1,
            }
        },
        "SIN takes one argument",
    );
    refused(
        |p| {
            f0(p).prints[0].items[0] = PrintItem::Value {
                slot: 1,
                whole: 1,
                frac: 30,
            }
        },
        "digits are 0 to 9",
    );
}
