//! The one error type of `io`: every reader and writer failure, naming the format, where in the
//! input it happened (line or byte offset) and what was expected, so a user can fix the file.

use crate::target::TargetError;
use std::fmt;

pub use super::formats::Format;

/// Where in the input something happened: a 1-based line for text, a 0-based byte offset for
/// binary data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// 1-based line number in a text file.
    Line(usize),
    /// 0-based byte offset.
    Byte(usize),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(l) => write!(f, "line {l}"),
            Location::Byte(b) => write!(f, "byte {b}"),
        }
    }
}

/// Why a file could not be read or written.
///
/// Every variant names the format; the reading ones say where (line or byte) and what was
/// expected. The messages are meant to be shown to users as they are.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IoError {
    /// The input has no bytes at all. Fix: check that the file was saved/copied completely.
    #[error("{}the file is empty (0 bytes)", fmt_format(.format))]
    Empty {
        /// The format suggested by the file name, if any.
        format: Option<Format>,
    },
    /// Neither the content nor the file name identify a supported format.
    #[error(
        "unrecognised file format: {reason}; supported: {}",
        super::formats::supported_formats()
    )]
    UnknownFormat {
        /// What was seen instead.
        reason: String,
    },
    /// The content is not what the format requires at this place. Fix: repair or re-export the
    /// file; the message says what was expected.
    #[error("{format}: {at}: expected {expected}, found {found}")]
    Syntax {
        format: Format,
        at: Location,
        expected: String,
        found: String,
    },
    /// The data ends before everything the header or syntax promised was read (a truncated
    /// download or copy, or a header that overstates its counts).
    #[error("{format}: unexpected end of data at {at}: expected {expected}")]
    Truncated {
        format: Format,
        at: Location,
        expected: String,
    },
    /// A header declares more elements than the file could possibly hold; refused before
    /// allocating anything (protects against huge allocations from corrupt headers).
    #[error("{format}: {at}: header declares {count} {element} but only {available} bytes follow (at least {needed} needed)")]
    CountTooLarge {
        format: Format,
        at: Location,
        element: String,
        count: u64,
        available: usize,
        needed: u128,
    },
    /// A face refers to a vertex that does not exist.
    #[error(
        "{format}: {at}: face {face} refers to vertex {index}, but there are {count} vertices"
    )]
    IndexOutOfRange {
        format: Format,
        at: Location,
        face: usize,
        index: i64,
        count: usize,
    },
    /// A coordinate is NaN or infinite. Fix: clean the input; `index` is the first bad vertex.
    #[error("{format}: {at}: vertex {index} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite {
        format: Format,
        at: Location,
        index: usize,
        x: f64,
        y: f64,
        z: f64,
    },
    /// A valid file using a feature LSW does not read (e.g. an external glTF buffer).
    #[error("{format}: {what} is not supported")]
    Unsupported { format: Format, what: String },
    /// The glTF crate rejected the document (JSON, GLB container or validation error).
    #[error("{format}: {message}")]
    Gltf { format: Format, message: String },
    /// The file parsed but the geometry is unusable as a target (e.g. no points).
    #[error("{format}: {source}")]
    Target {
        format: Format,
        #[source]
        source: TargetError,
    },
    /// A gzip or zlib stream inside the file is corrupt (bad header, checksum or deflate data).
    /// Fix: re-export or re-download the file; `at` is where the compressed stream starts.
    #[error("{format}: {at}: corrupt compressed data: {message}")]
    Decompress {
        format: Format,
        at: Location,
        message: String,
    },
    /// The operating system could not read or write a file (native only).
    #[error("cannot access {path}: {message}")]
    Fs { path: String, message: String },
    /// An output named for a format LSW does not write, or for no format (`what`: the format or
    /// the path).
    #[error(
        "cannot write {what}: LSW writes {}",
        super::formats::writable_extensions()
    )]
    NotWritable { what: String },
    /// A writer was given inconsistent input (index out of range, scalar array of the wrong
    /// length, invalid settings JSON, …).
    #[error("{format}: cannot write: {what}")]
    InvalidInput { format: Format, what: String },
}

fn fmt_format(f: &Option<Format>) -> String {
    f.map(|f| format!("{f}: ")).unwrap_or_default()
}

impl IoError {
    /// Shorthand for [`IoError::Syntax`].
    pub(crate) fn syntax(
        format: Format,
        at: Location,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> Self {
        IoError::Syntax {
            format,
            at,
            expected: expected.into(),
            found: found.into(),
        }
    }

    /// Shorthand for [`IoError::Truncated`].
    pub(crate) fn truncated(format: Format, at: Location, expected: impl Into<String>) -> Self {
        IoError::Truncated {
            format,
            at,
            expected: expected.into(),
        }
    }

    /// A one-sentence suggestion of what the user can do (the `hint` of the wasm facade's
    /// `{code, message, hint}`).
    pub fn hint(&self) -> &'static str {
        match self {
            IoError::Empty { .. } => "The file has no content; check that it was saved or copied completely.",
            IoError::UnknownFormat { .. } => super::formats::export_as_hint(),
            IoError::Syntax { .. } => "The file is damaged or not in the format it claims; re-export it from the original tool.",
            IoError::Truncated { .. } => "The file ends early; it was probably cut during download or copy.",
            IoError::CountTooLarge { .. } => "The header promises more data than the file holds; the file is truncated or its header is corrupt.",
            IoError::IndexOutOfRange { .. } => "A face refers to a missing vertex; repair the mesh or re-export it.",
            IoError::NonFinite { .. } => "Remove the points with NaN or infinite coordinates (the message names the first).",
            IoError::Unsupported { .. } => "Convert the file to a supported variant (e.g. GLB with embedded buffers, ASCII VTK).",
            IoError::Gltf { .. } => "The glTF document is invalid; check it with the Khronos glTF validator.",
            IoError::Target { .. } => "The file holds no usable points.",
            IoError::Decompress { .. } => "The compressed data is damaged; re-download or re-export the file.",
            IoError::Fs { .. } => "Check the path and the file permissions.",
            IoError::NotWritable { .. } => super::formats::name_output_hint(),
            IoError::InvalidInput { .. } => "This is a bug in the caller: the mesh passed to the writer is inconsistent.",
        }
    }

    /// A short stable code for the variant (used by the wasm facade's `{code, message, hint}`).
    pub fn code(&self) -> &'static str {
        match self {
            IoError::Empty { .. } => "io_empty",
            IoError::UnknownFormat { .. } => "io_unknown_format",
            IoError::Syntax { .. } => "io_syntax",
            IoError::Truncated { .. } => "io_truncated",
            IoError::CountTooLarge { .. } => "io_count_too_large",
            IoError::IndexOutOfRange { .. } => "io_index_out_of_range",
            IoError::NonFinite { .. } => "io_non_finite",
            IoError::Unsupported { .. } => "io_unsupported",
            IoError::Gltf { .. } => "io_gltf",
            IoError::Target { .. } => "io_target",
            IoError::Decompress { .. } => "io_decompress",
            IoError::Fs { .. } => "io_fs",
            IoError::NotWritable { .. } => "io_not_writable",
            IoError::InvalidInput { .. } => "io_invalid_input",
        }
    }
}
