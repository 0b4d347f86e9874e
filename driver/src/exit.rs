//! The documented exit codes of `fmsvm` (README "Exit codes").

/// How a run ended.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Exit {
    /// The program compiled (and ran to its end).
    Success = 0,
    /// A bug in fmsvm (it should never happen; please report it).
    Internal = 1,
    /// Bad command line (clap's own code).
    Usage = 2,
    /// The program has errors; nothing ran.
    Compile = 3,
    /// The program raised an alarm while running (the control would have stopped).
    Alarm = 4,
    /// A configured limit was reached (runaway loop, too much output).
    Limit = 5,
    /// A file could not be read or written.
    Io = 6,
    /// `--verify`: the output read back does not move as the kernel said (or cannot be read).
    Verify = 7,
    /// `dnc`: the serial port could not be opened or the device server not reached; nothing was sent.
    LinkOpen = 10,
    /// `dnc`: the link failed or closed while sending; the control has part of the program.
    LinkLost = 11,
    /// `dnc`: the control held XOFF (or CTS off) longer than `--hold-timeout`.
    LinkHeld = 12,
}

impl Exit {
    /// A file a flag names (`--params`, `--dialect-file`, `--offsets`, `--vars`, `--probe-points`)
    /// that is not in its format: the flag's argument is wrong, so it is a usage error, and the
    /// message gives the file and line.
    pub const MALFORMED_INPUT: Exit = Exit::Usage;
}

/// Why a request could not be carried out, typed: its exit code and the message a front end shows
/// (the command line on standard error, the editor in its diagnostics).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    pub exit: Exit,
    pub message: String,
}

impl Failure {
    /// `exit`, saying `message`.
    pub fn new(exit: Exit, message: impl Into<String>) -> Failure {
        Failure {
            exit,
            message: message.into(),
        }
    }

    /// Says the message as a plain error on standard error (the command line's rendering) and
    /// gives the exit code.
    pub fn say(self) -> Exit {
        crate::report::plain(&self.message);
        self.exit
    }
}
