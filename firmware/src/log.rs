//! Logging that costs nothing where there is no logger.
//!
//! The board binary logs through `defmt` (format strings stay on the host, the MCU sends
//! indices and raw arguments, so a log line costs a few bytes of flash and of semihosting
//! traffic). The same library also runs inside `fpgfx` and `fpgfx-sim`, which link no
//! defmt logger; there the macros expand to code that type-checks the arguments and is
//! never run. Use `{}` placeholders only, so both expansions accept the same strings.

#[cfg(feature = "defmt")]
macro_rules! log_info {
    ($($t:tt)*) => { defmt::info!($($t)*) };
}
#[cfg(feature = "defmt")]
macro_rules! log_warn {
    ($($t:tt)*) => { defmt::warn!($($t)*) };
}

#[cfg(not(feature = "defmt"))]
macro_rules! log_info {
    ($($t:tt)*) => {{
        if false {
            let _ = core::format_args!($($t)*);
        }
    }};
}
#[cfg(not(feature = "defmt"))]
macro_rules! log_warn {
    ($($t:tt)*) => {{
        if false {
            let _ = core::format_args!($($t)*);
        }
    }};
}

pub(crate) use {log_info, log_warn};
