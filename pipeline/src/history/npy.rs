//! `.npy` (NumPy format 1.0) float64 2-D arrays: a writer that appends rows and keeps the file
//! readable after every flush, and a reader for what it wrote.
//!
//! Header: magic `\x93NUMPY`, version 1.0, little-endian u16 header length, then the dict
//! `{'descr': '<f8', 'fortran_order': False, 'shape': (rows, cols), }` padded with spaces and a
//! final newline so that data starts at a multiple of 64 bytes. The shape field is padded to a
//! fixed width, so the header can be rewritten in place as rows are appended.

use crate::error::PipelineError;
use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

const HEADER_LEN: usize = 128;

fn header(rows: usize, cols: usize) -> Vec<u8> {
    let dict = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, {cols}), }}");
    let mut h = b"\x93NUMPY\x01\x00".to_vec();
    let body_len = HEADER_LEN - 10;
    h.extend_from_slice(&(body_len as u16).to_le_bytes());
    let mut body = dict.into_bytes();
    body.resize(body_len - 1, b' ');
    body.push(b'\n');
    h.extend_from_slice(&body);
    h
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> PipelineError + '_ {
    move |source| PipelineError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes a whole 2-D array (row-major `data`, `cols` columns) to `path`.
pub fn write_npy(path: &Path, data: &[f64], cols: usize) -> Result<(), PipelineError> {
    let rows = data.len().checked_div(cols).unwrap_or(0);
    let mut bytes = header(rows, cols);
    for v in data {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    crate::output::write_atomic(path, &bytes)
}

/// Appends rows to a `.npy` file; the header's row count is rewritten on every [`flush`].
///
/// [`flush`]: NpyAppender::flush
pub struct NpyAppender {
    path: PathBuf,
    file: BufWriter<File>,
    cols: usize,
    rows: usize,
}

impl NpyAppender {
    /// Creates (truncates) the file with zero rows.
    pub fn create(path: &Path, cols: usize) -> Result<Self, PipelineError> {
        let mut f = File::create(path).map_err(io(path))?;
        f.write_all(&header(0, cols)).map_err(io(path))?;
        Ok(Self {
            path: path.to_path_buf(),
            file: BufWriter::new(f),
            cols,
            rows: 0,
        })
    }

    /// Continues an array: `dst` gets the header and the first `rows` rows of `src` (written
    /// to a temporary file, fsync'd and renamed over `dst`, so a kill leaves either the old
    /// file or the new one; `src` may be `dst`), and is then open for appending. The caller
    /// has checked `src` ([`read_header`]: `cols` columns, at least `rows` rows).
    pub fn resume(src: &Path, dst: &Path, cols: usize, rows: usize) -> Result<Self, PipelineError> {
        let h = read_header(src)?;
        let tmp = dst.with_extension("npy.tmp");
        {
            let mut from = File::open(src).map_err(io(src))?;
            from.seek(SeekFrom::Start(h.data_offset as u64))
                .map_err(io(src))?;
            let mut to = BufWriter::new(File::create(&tmp).map_err(io(&tmp))?);
            to.write_all(&header(rows, cols)).map_err(io(&tmp))?;
            let want = (rows * cols * 8) as u64;
            let copied = std::io::copy(&mut from.take(want), &mut to).map_err(io(src))?;
            if copied != want {
                return Err(PipelineError::Input {
                    path: src.to_path_buf(),
                    message: format!("{copied} data bytes, expected {want} ({rows} rows)"),
                });
            }
            let f = to.into_inner().map_err(|e| io(&tmp)(e.into_error()))?;
            f.sync_all().map_err(io(&tmp))?;
        }
        std::fs::rename(&tmp, dst).map_err(io(dst))?;
        crate::output::sync_parent(dst).map_err(io(dst))?;
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .open(dst)
            .map_err(io(dst))?;
        f.seek(SeekFrom::End(0)).map_err(io(dst))?;
        Ok(Self {
            path: dst.to_path_buf(),
            file: BufWriter::new(f),
            cols,
            rows,
        })
    }

    /// Appends one row (its length must be `cols`).
    pub fn push(&mut self, row: &[f64]) -> Result<(), PipelineError> {
        if row.len() != self.cols {
            return Err(PipelineError::Output {
                path: self.path.clone(),
                message: format!("row of {} values, expected {}", row.len(), self.cols),
            });
        }
        for v in row {
            self.file
                .write_all(&v.to_le_bytes())
                .map_err(io(&self.path))?;
        }
        self.rows += 1;
        Ok(())
    }

    /// Rows written so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Writes buffered rows and the header's row count: the file is a valid array afterwards.
    pub fn flush(&mut self) -> Result<(), PipelineError> {
        let p = self.path.clone();
        self.file.flush().map_err(io(&p))?;
        let f = self.file.get_mut();
        f.seek(SeekFrom::Start(0)).map_err(io(&p))?;
        f.write_all(&header(self.rows, self.cols)).map_err(io(&p))?;
        f.seek(SeekFrom::End(0)).map_err(io(&p))?;
        f.sync_data().map_err(io(&p))
    }
}

/// The header of a float64 2-D `.npy` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NpyHeader {
    /// Rows the header declares.
    pub rows: usize,
    pub cols: usize,
    /// Byte offset of the first value.
    pub data_offset: usize,
    /// Complete rows of data in the file (may exceed `rows`: rows appended after the last
    /// header rewrite).
    pub data_rows: usize,
}

/// Reads the header of a float64 2-D `.npy` file (and counts the rows of data it holds).
pub fn read_header(path: &Path) -> Result<NpyHeader, PipelineError> {
    let mut f = File::open(path).map_err(io(path))?;
    let len = f.metadata().map_err(io(path))?.len() as usize;
    let mut head = vec![0u8; len.min(65536 + 12)];
    f.read_exact(&mut head).map_err(io(path))?;
    let (rows, cols, data_offset) = parse_header(path, &head)?;
    let data_rows = (len - data_offset.min(len)) / (8 * cols.max(1));
    Ok(NpyHeader {
        rows,
        cols,
        data_offset,
        data_rows,
    })
}

/// (rows, cols, data offset) of the header at the start of `bytes`.
fn parse_header(path: &Path, bytes: &[u8]) -> Result<(usize, usize, usize), PipelineError> {
    let bad = |m: &str| PipelineError::Input {
        path: path.to_path_buf(),
        message: m.to_string(),
    };
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err(bad("not a .npy file"));
    }
    let (hlen, start) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        _ if bytes.len() < 12 => return Err(bad("truncated header")),
        _ => (
            u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
            12,
        ),
    };
    let head = std::str::from_utf8(
        bytes
            .get(start..start + hlen)
            .ok_or_else(|| bad("truncated header"))?,
    )
    .map_err(|_| bad("header is not text"))?;
    if !head.contains("'<f8'") || head.contains("'fortran_order': True") {
        return Err(bad("only little-endian float64 C-order arrays are read"));
    }
    let shape = head
        .split("'shape': (")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .ok_or_else(|| bad("no shape in header"))?;
    let dims: Vec<usize> = shape
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().map_err(|_| bad("bad shape")))
        .collect::<Result<_, _>>()?;
    let (rows, cols) = match dims.as_slice() {
        [r, c] => (*r, *c),
        [r] => (*r, 1),
        _ => return Err(bad("not a 2-D array")),
    };
    Ok((rows, cols, start + hlen))
}

/// Reads a float64 2-D `.npy` array: (rows, cols, row-major data).
pub fn read_npy(path: &Path) -> Result<(usize, usize, Vec<f64>), PipelineError> {
    let mut bytes = Vec::new();
    File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(io(path))?;
    let bad = |m: &str| PipelineError::Input {
        path: path.to_path_buf(),
        message: m.to_string(),
    };
    let (rows, cols, offset) = parse_header(path, &bytes)?;
    let data_bytes = &bytes[offset..];
    let want = rows
        .checked_mul(cols)
        .and_then(|v| v.checked_mul(8))
        .ok_or_else(|| bad("shape too large"))?;
    if data_bytes.len() < want {
        return Err(bad("fewer values than the shape says"));
    }
    let data = data_bytes[..want]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
        .collect();
    Ok((rows, cols, data))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn append_flush_and_read_back() {
        let d = std::env::temp_dir().join(format!("squeal-npy-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.join("a.npy");
        let mut w = NpyAppender::create(&p, 3).unwrap();
        w.push(&[1.0, 2.0, 3.0]).unwrap();
        w.flush().unwrap();
        assert_eq!(read_npy(&p).unwrap(), (1, 3, vec![1.0, 2.0, 3.0]));
        w.push(&[4.0, 5.0, 6.5]).unwrap();
        w.flush().unwrap();
        let (r, c, v) = read_npy(&p).unwrap();
        assert_eq!((r, c), (2, 3));
        assert_eq!(v[5], 6.5);
        // Data starts at a multiple of 64 bytes (NumPy format 1.0 alignment).
        assert_eq!(HEADER_LEN % 64, 0);
        assert!(w.push(&[1.0]).is_err());
    }
}
