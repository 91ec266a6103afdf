//! The last line of defence around the `mcap` crate: a panic inside it becomes an error.

use crate::import::error::{at, ImportError};
use crate::import::sane;

/// Runs `f`, which calls into the `mcap` crate, turning a panic there into an error naming
/// the file (the last line of defence: [`crate::import::mcap_check`] checks the lengths
/// first). The panic's own message is not printed.
pub(super) fn contain_panic<T>(
    file: &str,
    f: impl FnOnce() -> Result<T, ImportError>,
) -> Result<T, ImportError> {
    use std::cell::Cell;
    use std::panic::{catch_unwind, AssertUnwindSafe};
    use std::sync::Once;
    thread_local! {
        static QUIET: Cell<bool> = const { Cell::new(false) };
    }
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let was = QUIET.with(|q| q.replace(true));
    let result = catch_unwind(AssertUnwindSafe(f));
    QUIET.with(|q| q.set(was));
    result.unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(at(
            file,
            "MCAP file",
            format!(
                "the MCAP reader failed ({}): expected a well-formed MCAP file",
                sane::quote(&what)
            ),
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_in_the_reader_becomes_an_error_naming_the_file() {
        let e = contain_panic::<()>("x.mcap", || panic!("range start index 9 out of range"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("x.mcap: MCAP file: the MCAP reader failed"),
            "{e}"
        );
        assert!(e.contains("range start index 9"), "{e}");
        // Later panics elsewhere are reported as usual (the hook is only quiet inside).
        assert_eq!(contain_panic("x", || Ok(3)), Ok(3));
    }
}
