//! NumPy `.npz` archives through two well-kept crates: [`zip`] writes and reads the archive
//! (members stored, not compressed, as `numpy.savez` writes them; ZIP64 for a member past
//! 4 GiB) and [`npyz`] each member's `.npy` header and little-endian data.  The arrays are
//! plain `f64` or `i32` vectors and 2-D `f64` blocks in C order.
//!
//! Every member's time stamp is the ZIP epoch (1980-01-01), so that the same problem writes the
//! same bytes (the set counts a QP written twice once, by its digest).

use std::collections::HashMap;
use std::io::{self, Read, Seek, Write};

use npyz::WriterBuilder;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipArchive, ZipWriter};

/// The data of one array, little-endian on disk.
#[derive(Debug, Clone, Copy)]
pub enum NpyData<'a> {
    /// `<f8` values.
    F64(&'a [f64]),
    /// `<i4` values.
    I32(&'a [i32]),
}

impl NpyData<'_> {
    fn len(&self) -> usize {
        match self {
            NpyData::F64(v) => v.len(),
            NpyData::I32(v) => v.len(),
        }
    }
}

/// One named array of an archive: its data in C order and its shape (empty: a scalar).
#[derive(Debug, Clone)]
pub struct NpyArray<'a> {
    /// Member name without `.npy` (the key `numpy.load(...)[name]` takes).
    pub name: &'a str,
    /// The values, row-major.
    pub data: NpyData<'a>,
    /// The shape; its product must equal the number of values (1 for `[]`).
    pub shape: Vec<usize>,
}

/// One array read back: its values as `f64` (`<i4` converted exactly) and its shape.
#[derive(Debug, Clone, PartialEq)]
pub struct NpyValues {
    /// The values, row-major.
    pub values: Vec<f64>,
    /// The shape (empty: a scalar).
    pub shape: Vec<usize>,
}

fn invalid(why: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, why)
}

/// Writes one array's `.npy` bytes (header and data) to `w`.
fn write_npy(w: &mut dyn Write, array: &NpyArray) -> io::Result<()> {
    let count: usize = array.shape.iter().product();
    if count != array.data.len() {
        return Err(invalid(format!(
            "array {}: shape {:?} holds {count} values, data has {}",
            array.name,
            array.shape,
            array.data.len()
        )));
    }
    let shape: Vec<u64> = array.shape.iter().map(|&d| d as u64).collect();
    match array.data {
        NpyData::F64(v) => write_values(w, &shape, v),
        NpyData::I32(v) => write_values(w, &shape, v),
    }
}

/// The `.npy` header of `values` (their default dtype: `<f8`, `<i4`) and the values.
fn write_values<T: npyz::AutoSerialize + Copy>(
    w: &mut dyn Write,
    shape: &[u64],
    values: &[T],
) -> io::Result<()> {
    let mut out = npyz::WriteOptions::<T>::new()
        .default_dtype()
        .shape(shape)
        .writer(w)
        .begin_nd()?;
    out.extend(values.iter().copied())?;
    out.finish()
}

/// Writes the arrays as one `.npz` archive (members `NAME.npy`, stored) to `w`, and gives `w`
/// back to be flushed (a set's files go into a staging directory renamed into place whole).
pub fn write_npz<W: Write + Seek>(w: W, arrays: &[NpyArray]) -> io::Result<W> {
    let mut zip = ZipWriter::new(w);
    for array in arrays {
        // A `.npy` header is at most a few hundred bytes; ZIP64 is needed past 4 GiB.
        let bytes = 8 * array.data.len() as u64 + 512;
        let options = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Stored)
            .last_modified_time(DateTime::default())
            .large_file(bytes >= u64::from(u32::MAX));
        zip.start_file(npyz::npz::file_name_from_array_name(array.name), options)?;
        write_npy(&mut zip, array)?;
    }
    Ok(zip.finish()?)
}

/// Every member of the `.npz` archive in `r`, by array name (`NAME.npy` → `NAME`); a member
/// that is not an `<f8` or `<i4` array is refused.
pub fn read_npz<R: Read + Seek>(r: R) -> io::Result<HashMap<String, NpyValues>> {
    let mut zip = ZipArchive::new(r)?;
    let mut out = HashMap::new();
    for k in 0..zip.len() {
        let member = zip.by_index(k)?;
        let file = member.name()?.into_owned();
        let name = npyz::npz::array_name_from_file_name(&file)
            .ok_or_else(|| invalid(format!("{file}: not an .npy member")))?
            .to_string();
        let npy = npyz::NpyFile::new(member)?;
        if npy.shape().len() > 1 && npy.order() != npyz::Order::C {
            return Err(invalid(format!(
                "{name}: Fortran order (only C order is read)"
            )));
        }
        let shape = npy.shape().iter().map(|&d| d as usize).collect();
        let values = match npy.dtype().descr().as_str() {
            "'<f8'" => npy.into_vec::<f64>()?,
            "'<i4'" => npy.into_vec::<i32>()?.into_iter().map(f64::from).collect(),
            other => return Err(invalid(format!("{name}: dtype {other}, not <f8 or <i4"))),
        };
        out.insert(name, NpyValues { values, shape });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What is written reads back: values, shapes (a scalar's empty one) and both dtypes.
    #[test]
    fn arrays_read_back_as_written() {
        let arrays = [
            NpyArray {
                name: "x",
                data: NpyData::F64(&[1.5, -2.0, 1e-300, 6.0]),
                shape: vec![2, 2],
            },
            NpyArray {
                name: "i",
                data: NpyData::I32(&[3, -7, i32::MAX]),
                shape: vec![3],
            },
            NpyArray {
                name: "s",
                data: NpyData::F64(&[42.0]),
                shape: vec![],
            },
        ];
        let bytes = write_npz(io::Cursor::new(Vec::new()), &arrays)
            .map(io::Cursor::into_inner)
            .unwrap_or_default();
        let back = read_npz(io::Cursor::new(bytes)).unwrap_or_default();
        assert_eq!(back.len(), 3);
        assert_eq!(back["x"].values, [1.5, -2.0, 1e-300, 6.0]);
        assert_eq!(back["x"].shape, [2, 2]);
        assert_eq!(back["i"].values, [3.0, -7.0, f64::from(i32::MAX)]);
        assert_eq!(back["s"].values, [42.0]);
        assert!(back["s"].shape.is_empty());
    }

    /// A shape that does not hold the data is refused, not written.
    #[test]
    fn a_wrong_shape_is_refused() {
        let arrays = [NpyArray {
            name: "x",
            data: NpyData::F64(&[1.0, 2.0]),
            shape: vec![3],
        }];
        assert!(write_npz(io::Cursor::new(Vec::new()), &arrays).is_err());
    }
}
