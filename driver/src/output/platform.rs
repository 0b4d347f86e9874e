//! What an output needs to know of the file system that differs between systems: what kind of
//! thing a name is, which file it is, and what a replaced file keeps. Unix reads the file type,
//! the device and inode, the mode and owner; elsewhere (Windows) the portable rules below, which
//! the unix tests exercise too (`portable`).

use std::fs::{self, File, FileType, Metadata};
use std::io;
use std::path::Path;

/// A name that is not a folder or a regular file.
#[cfg_attr(not(unix), allow(dead_code))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Special {
    /// A character device or a FIFO: written directly.
    Stream,
    /// A block device: refused.
    Disk,
    /// A socket: refused.
    Socket,
}

/// The kind of special file `t` is; None for a folder or a regular file.
#[cfg(unix)]
pub fn special(t: &FileType) -> Option<Special> {
    use std::os::unix::fs::FileTypeExt;
    if t.is_char_device() || t.is_fifo() {
        Some(Special::Stream)
    } else if t.is_block_device() {
        Some(Special::Disk)
    } else if t.is_socket() {
        Some(Special::Socket)
    } else {
        None
    }
}

/// Whether `t` is a FIFO (one reader: two outputs cannot share it).
#[cfg(unix)]
pub fn is_fifo(t: &FileType) -> bool {
    use std::os::unix::fs::FileTypeExt;
    t.is_fifo()
}

/// Which file a name is: its device and inode.
#[cfg(unix)]
pub type Identity = (u64, u64);

#[cfg(unix)]
pub fn identity(path: &Path) -> Option<Identity> {
    use std::os::unix::fs::MetadataExt;
    fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// What a replaced file keeps: its permissions and, where fmsvm may set it (root replacing another
/// user's file), its owner.
#[derive(Clone, Debug)]
pub struct Kept {
    permissions: fs::Permissions,
    #[cfg(unix)]
    owner: (u32, u32),
}

impl Kept {
    /// What `m`'s file keeps.
    pub fn of(m: &Metadata) -> Kept {
        #[cfg(unix)]
        use std::os::unix::fs::MetadataExt;
        Kept {
            permissions: m.permissions(),
            #[cfg(unix)]
            owner: (m.uid(), m.gid()),
        }
    }

    /// Gives the temporary file that replaces it the same.
    pub fn apply(&self, file: &File) -> io::Result<()> {
        file.set_permissions(self.permissions.clone())?;
        #[cfg(unix)]
        {
            let (uid, gid) = self.owner;
            // Keep the owner where we may; else the file is ours.
            let _ = std::os::unix::fs::fchown(file, Some(uid), Some(gid));
        }
        Ok(())
    }
}

/// A new output file gets the usual permissions: on unix 0666 less the umask (open(2) applies it),
/// as any new file (tempfile's own default is 0600).
pub fn new_file(builder: &mut tempfile::Builder<'_, '_>) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    #[cfg(not(unix))]
    let _ = builder;
}

#[cfg(not(unix))]
pub use portable::{Identity, identity, is_fifo, special};

/// The rules where the system tells only folders, files and links apart (Windows): any other
/// existing name (a device such as `COM1` or `NUL`) is written directly, and a file is known by its
/// canonical path (links followed; two hard links to one file are not seen as one).
#[cfg_attr(unix, allow(dead_code))]
mod portable {
    use super::*;

    pub fn special(t: &FileType) -> Option<Special> {
        (!t.is_dir() && !t.is_file()).then_some(Special::Stream)
    }

    pub fn is_fifo(_: &FileType) -> bool {
        false
    }

    pub type Identity = std::path::PathBuf;

    pub fn identity(path: &Path) -> Option<Identity> {
        fs::canonicalize(path).ok()
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn a_file_is_no_special_and_a_device_is_written_directly() {
            let dir = tempfile::tempdir().expect("a folder");
            let file = dir.path().join("part.nc");
            fs::write(&file, "G0 X0\n").expect("written");
            let of = |p: &Path| fs::metadata(p).map(|m| special(&m.file_type()));
            assert_eq!(of(&file).ok(), Some(None));
            assert_eq!(of(dir.path()).ok(), Some(None));
            #[cfg(unix)]
            assert_eq!(of(Path::new("/dev/null")).ok(), Some(Some(Special::Stream)));
        }

        #[test]
        fn two_spellings_of_one_file_are_one_identity_and_two_files_are_two() {
            let dir = tempfile::tempdir().expect("a folder");
            let a = dir.path().join("a.nc");
            let b = dir.path().join("b.nc");
            fs::write(&a, "").expect("written");
            fs::write(&b, "").expect("written");
            let again = dir.path().join(".").join("a.nc");
            assert_eq!(identity(&a), identity(&again));
            assert_ne!(identity(&a), identity(&b));
            assert_eq!(identity(&dir.path().join("none.nc")), None);
        }
    }
}
