//! NumPy `.npz` archives: named arrays of `f64`, `bool` or Unicode strings, each a `.npy` file
//! (NEP 1, format version 1.0, C order, little-endian) in an uncompressed zip, as
//! `numpy.savez` writes them and `numpy.load` reads them.
//!
//! Written here rather than with `ndarray-npy`, whose writer has no string arrays: the state,
//! input and output names belong in the archive beside the matrices they label.

use std::path::Path;

use anyhow::{Context, Result, bail};

/// One array's data.
#[derive(Debug, Clone, PartialEq)]
pub enum NpyData {
    F64(Vec<f64>),
    Bool(Vec<bool>),
    /// Fixed-width UTF-32 strings (`<U{n}`, n the longest string's characters).
    Str(Vec<String>),
}

/// A named array: its shape (row-major) and data.
#[derive(Debug, Clone, PartialEq)]
pub struct NpyArray {
    pub name: String,
    pub shape: Vec<usize>,
    pub data: NpyData,
}

impl NpyArray {
    pub fn new(name: &str, shape: &[usize], data: NpyData) -> Self {
        Self {
            name: name.to_owned(),
            shape: shape.to_vec(),
            data,
        }
    }

    fn len(&self) -> usize {
        match &self.data {
            NpyData::F64(v) => v.len(),
            NpyData::Bool(v) => v.len(),
            NpyData::Str(v) => v.len(),
        }
    }

    /// The `.npy` file: magic, version 1.0, the header dict padded with spaces so the data
    /// starts on a 64-byte boundary, then the data.
    pub fn to_npy(&self) -> Result<Vec<u8>> {
        if self.shape.iter().product::<usize>() != self.len() {
            bail!(
                "array `{}`: shape {:?} does not hold {} values",
                self.name,
                self.shape,
                self.len()
            );
        }
        let width = match &self.data {
            NpyData::Str(v) => v
                .iter()
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
                .max(1),
            _ => 0,
        };
        let descr = match &self.data {
            NpyData::F64(_) => "<f8".to_owned(),
            NpyData::Bool(_) => "|b1".to_owned(),
            NpyData::Str(_) => format!("<U{width}"),
        };
        let shape = match self.shape.as_slice() {
            [n] => format!("({n},)"),
            dims => format!(
                "({})",
                dims.iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        let mut header =
            format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
        // magic (6) + version (2) + header length (2) + header + '\n' ≡ 0 (mod 64)
        let unpadded = 10 + header.len() + 1;
        header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
        header.push('\n');
        let header_len = u16::try_from(header.len())
            .with_context(|| format!("array `{}`: header too long", self.name))?;
        let mut bytes = Vec::with_capacity(header.len() + 10 + 8 * self.len());
        bytes.extend_from_slice(b"\x93NUMPY\x01\x00");
        bytes.extend_from_slice(&header_len.to_le_bytes());
        bytes.extend_from_slice(header.as_bytes());
        match &self.data {
            NpyData::F64(v) => v
                .iter()
                .for_each(|x| bytes.extend_from_slice(&x.to_le_bytes())),
            NpyData::Bool(v) => bytes.extend(v.iter().map(|&b| u8::from(b))),
            NpyData::Str(v) => {
                for s in v {
                    let mut chars = 0;
                    for c in s.chars() {
                        bytes.extend_from_slice(&u32::from(c).to_le_bytes());
                        chars += 1;
                    }
                    bytes.extend(std::iter::repeat_n(0u8, 4 * (width - chars)));
                }
            }
        }
        Ok(bytes)
    }
}

/// Writes `arrays` to the `.npz` archive at `path` (`name.npy` members, stored uncompressed),
/// whole or not at all.
pub fn write_npz(path: &Path, arrays: &[NpyArray]) -> Result<()> {
    let members = arrays
        .iter()
        .map(|array| Ok((format!("{}.npy", array.name), array.to_npy()?)))
        .collect::<Result<Vec<_>>>()?;
    let archive = crate::output::zip_archive(&members)
        .with_context(|| format!("writing {}", path.display()))?;
    crate::output::write_file(path, archive)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The header `np.save` writes for `np.zeros((3, 4))` (NEP 1, numpy's 64-byte alignment):
    /// the dict padded with spaces and a newline, the data from byte 128.
    #[test]
    fn header_is_numpys() {
        let a = NpyArray::new("a", &[3, 4], NpyData::F64(vec![0.0; 12]));
        let bytes = a.to_npy().unwrap();
        let expected_header = "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }";
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + len) % 64, 0);
        let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
        assert!(header.starts_with(expected_header), "{header}");
        assert!(header.ends_with('\n'));
        assert_eq!(bytes.len(), 10 + len + 96);
    }

    #[test]
    fn strings_are_fixed_width_utf32() {
        let a = NpyArray::new("n", &[2], NpyData::Str(vec!["ab".into(), "α".into()]));
        let bytes = a.to_npy().unwrap();
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
        assert!(
            header.contains("'descr': '<U2'") && header.contains("(2,)"),
            "{header}"
        );
        let data = &bytes[10 + len..];
        assert_eq!(data.len(), 16);
        assert_eq!(&data[..4], &u32::from('a').to_le_bytes());
        assert_eq!(&data[8..12], &0x3b1u32.to_le_bytes());
        assert_eq!(&data[12..], &[0; 4]);
    }

    #[test]
    fn a_shape_that_does_not_fit_is_refused() {
        let a = NpyArray::new("a", &[2, 2], NpyData::Bool(vec![true; 3]));
        assert!(
            a.to_npy()
                .unwrap_err()
                .to_string()
                .contains("does not hold")
        );
    }
}
