//! A minimal NumPy `.npz` writer: a ZIP archive (stored, not compressed) of `.npy` files, the
//! format `numpy.load` reads (and `numpy.savez` writes).  No dependency: the ZIP headers and the
//! CRC-32 each member needs are a few dozen lines, and the arrays we write are plain
//! little-endian `f64` or `i32` vectors (and 2-D `f64` blocks), so `.npy`'s version 1.0 header
//! suffices.
//!
//! Limits: ZIP32 only (every offset and size below 4 GiB — a problem of 10⁶ unknowns takes about
//! 0.3 GiB), refused with an error otherwise rather than written wrongly.

use std::io::{self, Write};

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

    fn descr(&self) -> &'static str {
        match self {
            NpyData::F64(_) => "<f8",
            NpyData::I32(_) => "<i4",
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

/// The `.npy` (version 1.0) bytes of one array.
pub fn npy_bytes(array: &NpyArray) -> io::Result<Vec<u8>> {
    let count: usize = array.shape.iter().product();
    if count != array.data.len() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "array {}: shape {:?} holds {count} values, data has {}",
                array.name,
                array.shape,
                array.data.len()
            ),
        ));
    }
    let shape = match array.shape.as_slice() {
        [] => "()".to_string(),
        [n] => format!("({n},)"),
        dims => format!(
            "({})",
            dims.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header = format!(
        "{{'descr': '{}', 'fortran_order': False, 'shape': {shape}, }}",
        array.data.descr()
    );
    // Magic (6) + version (2) + length (2) + header, padded with spaces to a multiple of 64
    // and ended by a newline, as the format asks.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    header.push('\n');
    let header_len = u16::try_from(header.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "npy header too long"))?;
    let mut out = Vec::with_capacity(10 + header.len() + 8 * array.data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&header_len.to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    match array.data {
        NpyData::F64(v) => v
            .iter()
            .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
        NpyData::I32(v) => v
            .iter()
            .for_each(|x| out.extend_from_slice(&x.to_le_bytes())),
    }
    Ok(out)
}

/// The CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320) table.
const CRC_TABLE: [u32; 256] = {
    let mut table = [0u32; 256];
    let mut i = 0;
    while i < 256 {
        let mut c = i as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
            k += 1;
        }
        table[i] = c;
        i += 1;
    }
    table
};

/// CRC-32 of `bytes`, as ZIP stores it.
pub fn crc32(bytes: &[u8]) -> u32 {
    !bytes.iter().fold(!0u32, |c, &b| {
        CRC_TABLE[((c ^ u32::from(b)) & 0xFF) as usize] ^ (c >> 8)
    })
}

fn too_large() -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        "npz archive beyond 4 GiB (ZIP64 is not written)",
    )
}

fn u32_of(n: usize) -> io::Result<u32> {
    u32::try_from(n).map_err(|_| too_large())
}

/// DOS date 1980-01-01, time 00:00: fixed, so that the same problem writes the same bytes.
const DOS_DATE: u16 = (1 << 5) | 1;

/// Writes the arrays as one `.npz` archive (members `NAME.npy`, stored) to `w`.
pub fn write_npz(w: &mut dyn Write, arrays: &[NpyArray]) -> io::Result<()> {
    let mut central = Vec::new();
    let mut offset = 0usize;
    for array in arrays {
        let name = format!("{}.npy", array.name);
        let data = npy_bytes(array)?;
        let (crc, size, at) = (crc32(&data), u32_of(data.len())?, u32_of(offset)?);
        let name_len = u16::try_from(name.len()).map_err(|_| too_large())?;
        let mut local = Vec::with_capacity(30 + name.len());
        local.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        for v in [20u16, 0, 0, 0, DOS_DATE] {
            local.extend_from_slice(&v.to_le_bytes()); // version, flags, stored, time, date
        }
        for v in [crc, size, size] {
            local.extend_from_slice(&v.to_le_bytes());
        }
        local.extend_from_slice(&name_len.to_le_bytes());
        local.extend_from_slice(&0u16.to_le_bytes());
        local.extend_from_slice(name.as_bytes());
        w.write_all(&local)?;
        w.write_all(&data)?;
        central.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
        for v in [20u16, 20, 0, 0, 0, DOS_DATE] {
            central.extend_from_slice(&v.to_le_bytes()); // made by, needed, flags, method, time, date
        }
        for v in [crc, size, size] {
            central.extend_from_slice(&v.to_le_bytes());
        }
        for v in [name_len, 0, 0, 0, 0] {
            central.extend_from_slice(&v.to_le_bytes()); // name, extra, comment, disk, internal
        }
        central.extend_from_slice(&0u32.to_le_bytes()); // external attributes
        central.extend_from_slice(&at.to_le_bytes());
        central.extend_from_slice(name.as_bytes());
        offset += local.len() + data.len();
    }
    let entries = u16::try_from(arrays.len()).map_err(|_| too_large())?;
    let (cd_size, cd_offset) = (u32_of(central.len())?, u32_of(offset)?);
    u32_of(offset + central.len())?;
    w.write_all(&central)?;
    let mut end = Vec::with_capacity(22);
    end.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    for v in [0u16, 0, entries, entries] {
        end.extend_from_slice(&v.to_le_bytes());
    }
    end.extend_from_slice(&cd_size.to_le_bytes());
    end.extend_from_slice(&cd_offset.to_le_bytes());
    end.extend_from_slice(&0u16.to_le_bytes());
    w.write_all(&end)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The check value of CRC-32/ISO-HDLC (the ZIP one) is CBF43926 for "123456789".
    #[test]
    fn crc32_matches_the_standard_check_value() {
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    }

    /// The header of a 3-vector is the one numpy writes for `np.save(f, np.zeros(3))`, padded
    /// so that the data start at byte 128 (numpy ≥ 1.x pads to 64; its text is fixed).
    #[test]
    fn npy_header_is_numpy_s() {
        let bytes = npy_bytes(&NpyArray {
            name: "x",
            data: NpyData::F64(&[0.0; 3]),
            shape: vec![3],
        })
        .unwrap_or_default();
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + len) % 64, 0);
        let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap_or("");
        assert!(header.starts_with("{'descr': '<f8', 'fortran_order': False, 'shape': (3,), }"));
        assert!(header.ends_with('\n'));
        assert_eq!(bytes.len(), 10 + len + 24);
    }
}
