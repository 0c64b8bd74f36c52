//! Why a command could not be packed or a record string not unpacked.

/// Why a command could not be packed or a record string not unpacked. Every variant names
/// the field and the value, so that the host can tell the user which vertex of which
/// command does not fit the board.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BusError {
    /// A value does not fit its field.
    #[error("{layout}: field `{field}` = {value} is outside {min}..={max}")]
    OutOfRange {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`](crate::bus::fields) names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The offending value.
        value: i64,
        /// Smallest allowed value.
        min: i64,
        /// Largest allowed value.
        max: i64,
    },
    /// A coordinate has more fraction bits than the layout carries.
    #[error("{layout}: field `{field}` = {value} has fraction bits below the layout's {layout_bits} sub-pixel bits")]
    SubpixelPrecision {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`](crate::bus::fields) names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The value in the caller's sub-pixel units.
        value: i64,
        /// The layout's sub-pixel bits.
        layout_bits: u8,
    },
    /// An 8-bit layout was given a colour that is not exactly an RGB332 value.
    #[error(
        "{layout}: field `{field}` = #{value:06x} is not an RGB332 colour (use quantize_rgb332)"
    )]
    ColorNotRepresentable {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`](crate::bus::fields) names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The colour as 0xRRGGBB.
        value: u32,
    },
    /// The layout has no such command.
    #[error("{layout}: cannot carry {command} commands")]
    UnsupportedCommand {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// [`Kind::name`](crate::bus::Kind::name) of the command.
        command: &'static str,
    },
    /// The command uses a feature the layout lacks.
    #[error("{layout}: has no field for `{field}` (value {value})")]
    UnsupportedFeature {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field that would be needed.
        field: &'static str,
        /// The value that could not be sent.
        value: i64,
    },
    /// An opcode or enumeration value that names nothing.
    #[error("{layout}: field `{field}` = {value} is not a valid code")]
    InvalidCode {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`](crate::bus::fields) names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The value read from the records.
        value: u64,
    },
    /// A channel (SPI address) the layout does not use.
    #[error("{layout}: no command port at channel {channel:#04x}")]
    UnknownChannel {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The SPI address given.
        channel: u8,
    },
    /// A record has bits set above the record width.
    #[error("record {index} = {value:#x} is wider than {record_bits} bits")]
    RecordTooWide {
        /// Index of the record.
        index: usize,
        /// The record as given, with bits set above `record_bits`.
        value: u64,
        /// The layout's record width.
        record_bits: u8,
    },
    /// The output buffer (or [`MAX_RECORDS`](crate::bus::MAX_RECORDS)) is too small for the packet.
    #[error("packet needs more than {capacity} records")]
    BufferTooSmall {
        /// Records available.
        capacity: usize,
    },
    /// The records end before the packet does.
    #[error("packet needs {needed} bits but the records hold {available}")]
    Truncated {
        /// Bits needed so far.
        needed: usize,
        /// Bits available.
        available: usize,
    },
    /// More records were given than the packet uses.
    #[error("packet uses {used} records but {given} were given")]
    TrailingRecords {
        /// Records the packet occupies.
        used: usize,
        /// Records passed in.
        given: usize,
    },
    /// Padding bits are not zero: the records are misaligned or corrupt.
    #[error("padding bits are not zero ({bits} bits = {value:#x})")]
    NonZeroPadding {
        /// Number of padding bits.
        bits: usize,
        /// The padding bits as read.
        value: u64,
    },
    /// A field wider than 64 bits or a record width outside 1…64.
    #[error("bad width {0}")]
    BadWidth(u8),
    /// A [`BusLayout`](crate::bus::BusLayout) whose numbers make no bus (see [`BusLayout::validate`](crate::bus::BusLayout::validate)).
    #[error("layout {layout}: {reason}")]
    BadLayout {
        /// [`BusLayout::name`](crate::bus::BusLayout::name) of the refusing layout, so the message says which board.
        layout: &'static str,
        /// Which rule of [`BusLayout::validate`](crate::bus::BusLayout::validate) the numbers break.
        reason: &'static str,
    },
}
