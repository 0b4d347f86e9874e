//! The editor's view of arbitrary text (`fmsvm lsp`): the outline never panics, and every item's
//! span lies in the text on character boundaries (the server turns them into line and column).
#![no_main]
use libfuzzer_sys::fuzz_target;

use fmsvm_compiler::outline::{Item, outline};
use fmsvm_compiler::{FileId, Options, Syntax};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    for syntax in [Syntax::FANUC, Syntax::HAAS, Syntax::NCT] {
        let options = Options {
            syntax,
            ..Options::default()
        };
        for item in outline(FileId(0), text, &options) {
            let mut spans = vec![item.span()];
            if let Item::Loop { end: Some(e), .. } = &item {
                spans.push(*e);
            }
            if let Item::Program { whole, .. } = &item {
                spans.push(*whole);
            }
            for s in spans {
                let (a, b) = (s.start as usize, s.end as usize);
                assert!(a <= b && b <= text.len(), "{item:?} outside the text");
                assert!(text.is_char_boundary(a) && text.is_char_boundary(b), "{item:?}");
            }
        }
    }
});
