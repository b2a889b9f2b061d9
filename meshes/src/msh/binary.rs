//! Bounds-checked reading of the little-endian binary blocks of a 4.1 binary `.msh` file
//! (int = 4 bytes, size_t = data-size = 8 bytes, double = 8 bytes).

use crate::MeshError;

/// A cursor over a binary block; errors name the section's first line and the byte offset.
pub(crate) struct Bin<'a> {
    bytes: &'a [u8],
    pub pos: usize,
    file: &'a str,
    /// Line of the section header, for error messages.
    line: usize,
    section: &'static str,
}

impl<'a> Bin<'a> {
    pub fn new(
        bytes: &'a [u8],
        pos: usize,
        file: &'a str,
        line: usize,
        section: &'static str,
    ) -> Self {
        Bin {
            bytes,
            pos,
            file,
            line,
            section,
        }
    }

    /// Bytes left after the cursor.
    pub fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }

    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N], MeshError> {
        let end = self.pos.checked_add(N).filter(|&e| e <= self.bytes.len());
        match end {
            Some(e) => {
                let mut out = [0u8; N];
                out.copy_from_slice(&self.bytes[self.pos..e]);
                self.pos = e;
                Ok(out)
            }
            None => Err(self.err(format!(
                "binary ${} ends before {what} at byte offset {} (truncated file?)",
                self.section, self.pos
            ))),
        }
    }

    /// A 4-byte signed int.
    pub fn int(&mut self, what: &str) -> Result<i32, MeshError> {
        Ok(i32::from_le_bytes(self.take::<4>(what)?))
    }

    /// An 8-byte size_t (counts and node/element tags).
    pub fn size(&mut self, what: &str) -> Result<u64, MeshError> {
        Ok(u64::from_le_bytes(self.take::<8>(what)?))
    }

    /// A count that must fit in memory: at most the bytes left divided by `min_bytes` each.
    pub fn count(&mut self, what: &str, min_bytes: usize) -> Result<usize, MeshError> {
        let at = self.pos;
        let n = self.size(what)?;
        let max = self.remaining() / min_bytes.max(1);
        match usize::try_from(n) {
            Ok(n) if n <= max => Ok(n),
            _ => Err(self.err(format!(
                "binary ${}: {what} {n} at byte offset {at} does not fit in the {} bytes left (corrupt or truncated file?)",
                self.section,
                self.remaining()
            ))),
        }
    }

    /// A finite 8-byte double.
    pub fn real(&mut self, what: &str) -> Result<f64, MeshError> {
        let at = self.pos;
        let v = f64::from_le_bytes(self.take::<8>(what)?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(format!(
                "binary ${}: {what} at byte offset {at} is {v}",
                self.section
            )))
        }
    }

    pub fn err(&self, message: String) -> MeshError {
        MeshError::parse(self.file, self.line, message)
    }
}
