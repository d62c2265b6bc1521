//! The crate's error type.
//!
//! Every error that concerns a file names it first (`sky.exr: no RGB
//! channels ...`), so a command can print the message as is. Errors found
//! without a file at hand (an image size that fits no layout) are given their
//! file later with [`Error::in_file`].

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// Result with this crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong loading, saving or building an environment map.
///
/// The messages are meant for users: they name the file, say what is wrong
/// and, where there is a choice to make, how to make it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be opened or read.
    #[error("{}: cannot read: {source}", .path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },

    /// A file could not be written (including creating its temporary file
    /// or renaming that into place).
    #[error("{}: cannot write: {source}", .path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },

    /// A file's contents are not a valid image of its format (truncated,
    /// corrupt, or a feature the decoder does not support).
    #[error("{}: cannot decode {format}: {message}", .path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// The format it was read as (`"PNG"`, `"OpenEXR"`, ...).
        format: &'static str,
        /// What the decoder reported.
        message: String,
    },

    /// An image could not be encoded.
    #[error("{}: cannot encode {format}: {message}", .path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// The format (`"PNG"`, `"OpenEXR"`, ...).
        format: &'static str,
        /// What the encoder reported.
        message: String,
    },

    /// The file name's extension names no format this crate reads or writes.
    #[error("{}: {}; accepted: {accepted}", .path.display(), describe_extension(.extension))]
    UnknownExtension {
        /// The file.
        path: PathBuf,
        /// Its extension, if it has one.
        extension: Option<String>,
        /// The accepted extensions, comma-separated.
        accepted: &'static str,
    },

    /// An OpenEXR file has no layer with R, G and B channels.
    #[error("{}: no RGB channels (an R, G and B channel in one layer are needed; found: {found})", .path.display())]
    MissingChannels {
        /// The file.
        path: PathBuf,
        /// The channels the file has, comma-separated.
        found: String,
    },

    /// An image is larger than the configured limit; checked before any
    /// pixel memory is allocated.
    #[error("image is {width}×{height} ({texels} texels), above the limit of {limit} texels")]
    TooLarge {
        /// Width in texels.
        width: u64,
        /// Height in texels.
        height: u64,
        /// `width × height` (times six for a six-file cube).
        texels: u64,
        /// The limit.
        limit: u64,
    },

    /// An image's size or representation does not fit the layout asked for
    /// or detected (wrong aspect ratio, an ambiguous square, a layout the
    /// mapping does not have).
    #[error("{0}")]
    Layout(String),

    /// A line of text input (a direction for `map`, a chart point for
    /// `unmap`; see `envmap_cli::text`) is malformed or has no mapping. The
    /// message names no file: the caller adds the file and line number.
    #[error("{0}")]
    Input(String),

    /// A pixel buffer's length does not match the image's size.
    #[error("{len} pixels given for a {width}×{height} image")]
    PixelCount {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// Length of the buffer given.
        len: usize,
    },

    /// A face of a six-file cube is missing, not square, or not the size of
    /// the others.
    #[error("{}: {message}", .path.display())]
    CubeFaces {
        /// The offending face file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },

    /// Saving would replace an input file, and that was not asked for.
    #[error(
        "{}: refusing to write over the input file (choose another output name, or ask to overwrite the input)",
        .path.display()
    )]
    WouldOverwriteInput {
        /// The output path that is also an input.
        path: PathBuf,
    },

    /// A name given for a layout or option is not known.
    #[error("unknown {what} {name:?}; expected one of: {expected}")]
    UnknownName {
        /// What kind of name (`"layout"`, `"mapping"`).
        what: &'static str,
        /// The name given.
        name: String,
        /// The accepted names, comma-separated.
        expected: String,
    },

    /// An option's value is out of its range, or options disagree (a
    /// supercompression level, zstd outside KTX2, a layout that is not a
    /// cube's, a level count a chain cannot have).
    #[error("{message}")]
    Options {
        /// What is wrong, and what would be accepted.
        message: String,
    },

    /// Something a format, or this build, cannot do (write a read-only texel
    /// format, a texture as six files, zstd without the `zstd` feature).
    #[error("{message}")]
    Unsupported {
        /// What was asked, and what can be done instead.
        message: String,
    },

    /// Sizes that do not fit together: a texture's levels and faces, a
    /// chain's level sizes, a lit environment's levels and roughness values.
    #[error("{message}")]
    Dimensions {
        /// Which sizes, and what they should be.
        message: String,
    },

    /// Texels hold NaN or infinite values where finite ones are needed (the
    /// bake's input; `LoadOptions::non_finite` replaces them on loading).
    #[error("{texels} texels hold NaN or infinite values; replace them first (envmap bake does, as convert does)")]
    NonFiniteTexels {
        /// How many.
        texels: u64,
    },

    /// An encoder or a container library failed (Zstandard, the DDS
    /// header); the file is named by [`Error::in_file`] where known.
    #[error("{message}")]
    Codec {
        /// The format (`"KTX2"`, `"DDS"`).
        format: &'static str,
        /// What the library reported.
        message: String,
    },

    /// A call the API does not take in this state (an in-memory run
    /// committed to files, a texture staged as an image).
    #[error("{message}")]
    Usage {
        /// What was called, and what to call instead.
        message: String,
    },

    /// A mesh's positions and normals differ in number.
    #[error("mesh has {positions} positions but {normals} normals")]
    MeshCounts {
        /// Number of positions.
        positions: usize,
        /// Number of normals.
        normals: usize,
    },

    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index}, but the mesh has {vertices} vertices")]
    MeshIndex {
        /// The triangle's index.
        triangle: usize,
        /// The offending vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },

    /// A mesh position is NaN or infinite.
    #[error("vertex {vertex} has a non-finite position {position:?}")]
    MeshPosition {
        /// The vertex's index.
        vertex: usize,
        /// Its position.
        position: envmap_core::glam::Vec3,
    },

    /// A mesh normal is NaN, infinite or not of unit length.
    #[error("vertex {vertex} has normal {normal:?}, which is not a finite unit vector")]
    MeshNormal {
        /// The vertex's index.
        vertex: usize,
        /// Its normal.
        normal: envmap_core::glam::Vec3,
    },

    /// Bézier patch data (the teapot's `.bpt` format) could not be read.
    #[error("patch data, line {line}: {message}")]
    PatchData {
        /// 1-based line number.
        line: usize,
        /// What was expected there.
        message: String,
    },

    /// The operation was cancelled through its `cancel` flag (see
    /// [`crate::cancel`]) before it finished; nothing it was writing was
    /// left behind.
    #[error("cancelled")]
    Cancelled,

    /// A file format this build of the library was made without (its
    /// Cargo feature off; `envmap-render`'s defaults have every one).
    #[error("{}: {format} files need envmap-render's `{feature}` feature, which this build was made without", .path.display())]
    FormatDisabled {
        /// The file.
        path: PathBuf,
        /// The format (`"OpenEXR"`, `"KTX2"`, ...).
        format: &'static str,
        /// The Cargo feature that has it.
        feature: &'static str,
    },

    /// An error that names no file, given the file it concerns.
    #[error("{}: {source}", .path.display())]
    InFile {
        /// The file.
        path: PathBuf,
        /// The error.
        source: Box<Error>,
    },
}

impl Error {
    /// This error, naming `path` if it names no file yet (errors that already
    /// name one are returned unchanged).
    #[must_use]
    pub fn in_file(self, path: &Path) -> Error {
        if self.path().is_some() {
            self
        } else {
            Error::InFile {
                path: path.to_path_buf(),
                source: Box::new(self),
            }
        }
    }

    /// The file this error concerns, if any.
    #[must_use]
    pub fn path(&self) -> Option<&Path> {
        match self {
            Error::Read { path, .. }
            | Error::Write { path, .. }
            | Error::Decode { path, .. }
            | Error::Encode { path, .. }
            | Error::UnknownExtension { path, .. }
            | Error::MissingChannels { path, .. }
            | Error::CubeFaces { path, .. }
            | Error::WouldOverwriteInput { path }
            | Error::FormatDisabled { path, .. }
            | Error::InFile { path, .. } => Some(path),
            Error::TooLarge { .. }
            | Error::Layout(_)
            | Error::Input(_)
            | Error::Options { .. }
            | Error::Unsupported { .. }
            | Error::Dimensions { .. }
            | Error::NonFiniteTexels { .. }
            | Error::Codec { .. }
            | Error::Usage { .. }
            | Error::MeshCounts { .. }
            | Error::MeshIndex { .. }
            | Error::MeshPosition { .. }
            | Error::MeshNormal { .. }
            | Error::PatchData { .. }
            | Error::PixelCount { .. }
            | Error::UnknownName { .. }
            | Error::Cancelled => None,
        }
    }

    pub(crate) fn options(message: impl fmt::Display) -> Error {
        Error::Options {
            message: message.to_string(),
        }
    }

    pub(crate) fn unsupported(message: impl fmt::Display) -> Error {
        Error::Unsupported {
            message: message.to_string(),
        }
    }

    pub(crate) fn dimensions(message: impl fmt::Display) -> Error {
        Error::Dimensions {
            message: message.to_string(),
        }
    }

    pub(crate) fn usage(message: impl fmt::Display) -> Error {
        Error::Usage {
            message: message.to_string(),
        }
    }

    #[cfg(any(feature = "ktx2", feature = "dds"))]
    pub(crate) fn codec(format: &'static str, message: impl fmt::Display) -> Error {
        Error::Codec {
            format,
            message: message.to_string(),
        }
    }

    pub(crate) fn layout(message: impl fmt::Display) -> Error {
        Error::Layout(message.to_string())
    }

    pub(crate) fn read(path: &Path, source: io::Error) -> Error {
        Error::Read {
            path: path.to_path_buf(),
            source,
        }
    }

    pub(crate) fn write(path: &Path, source: io::Error) -> Error {
        Error::Write {
            path: path.to_path_buf(),
            source,
        }
    }
}

fn describe_extension(ext: &Option<String>) -> String {
    match ext {
        Some(e) => format!("unknown image extension \".{e}\""),
        None => "no file extension to tell the image format".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_file() {
        let e = Error::MissingChannels {
            path: "sky.exr".into(),
            found: "Y".into(),
        };
        assert!(e.to_string().starts_with("sky.exr: no RGB channels"));
        let e = Error::layout("image is 1000×333").in_file(Path::new("input.png"));
        assert_eq!(e.to_string(), "input.png: image is 1000×333");
        // Already named: unchanged.
        let e = e.in_file(Path::new("other.png"));
        assert_eq!(e.path(), Some(Path::new("input.png")));
        let e = Error::write(
            Path::new("out.png"),
            io::Error::from(io::ErrorKind::PermissionDenied),
        );
        assert!(e
            .to_string()
            .starts_with("out.png: cannot write: permission denied"));
    }
}
