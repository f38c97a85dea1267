//! The `tensor_file` container of Mitsuba and the RGL material database (Dupuy & Jakob 2018).
//!
//! Layout, little-endian:
//! - bytes 0..12: the magic `"tensor_file\0"`; bytes 12, 13: version 1.0; then a `u32` field count;
//! - per field: `u16` name length, the name, `u16` rank, `u8` dtype, `u64` byte offset of the
//!   data from the start of the file, then `rank` sizes as `u64`;
//! - dtype codes: 1 u8, 2 i8, 3 u16, 4 i16, 5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64.
//!
//! Only the parts Specula needs are decoded: any field is located and bounds-checked, and
//! `f32` and `u8` fields can be read out. [`encode`] writes the same layout, each field's data
//! aligned to 8 bytes (Mitsuba maps the file and reads the arrays in place).

use crate::malformed::Malformed;
use std::collections::HashMap;

/// The longest field name read, bytes (Mitsuba's and the RGL database's are under 16:
/// `theta_i`, `vndf`, `luminance`, `description`). Every length field of the header is
/// checked against a bound like this one, or against the bytes left, before it is used.
const MAX_FIELD_NAME_BYTES: usize = 64;

/// The highest rank of a field read (the RGL files' largest is 5).
const MAX_RANK: usize = 8;

/// Bytes of the smallest field entry of the header: name length, rank, dtype, offset.
const MIN_FIELD_ENTRY_BYTES: usize = 2 + 2 + 1 + 8;

/// The first 12 bytes of every tensor file.
pub const MAGIC: &[u8; 12] = b"tensor_file\0";

/// Element type of a field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Dtype {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    U64,
    I64,
    F16,
    F32,
    F64,
}

impl Dtype {
    fn from_code(code: u8) -> Option<Self> {
        use Dtype::*;
        Some(match code {
            1 => U8,
            2 => I8,
            3 => U16,
            4 => I16,
            5 => U32,
            6 => I32,
            7 => U64,
            8 => I64,
            9 => F16,
            10 => F32,
            11 => F64,
            _ => return None,
        })
    }

    /// The code of this type in the field table.
    pub(super) fn code(self) -> u8 {
        use Dtype::*;
        match self {
            U8 => 1,
            I8 => 2,
            U16 => 3,
            I16 => 4,
            U32 => 5,
            I32 => 6,
            U64 => 7,
            I64 => 8,
            F16 => 9,
            F32 => 10,
            F64 => 11,
        }
    }

    /// Size of one element in bytes.
    pub(super) fn size_bytes(self) -> usize {
        use Dtype::*;
        match self {
            U8 | I8 => 1,
            U16 | I16 | F16 => 2,
            U32 | I32 | F32 => 4,
            U64 | I64 | F64 => 8,
        }
    }
}

/// One named array of a tensor file: its type, shape and where its bytes are.
#[derive(Debug, Clone)]
pub(super) struct Field {
    pub dtype: Dtype,
    pub shape: Vec<usize>,
    data_start: usize,
    data_len: usize,
}

/// One named array to write: its element type, shape and little-endian bytes.
#[derive(Debug, Clone)]
pub(super) struct FieldData {
    pub name: String,
    pub dtype: Dtype,
    pub shape: Vec<usize>,
    pub bytes: Vec<u8>,
}

impl FieldData {
    /// An `f32` array of the given shape (whose product is `values.len()`).
    pub(super) fn f32(name: &str, shape: &[usize], values: &[f32]) -> Self {
        debug_assert_eq!(shape.iter().product::<usize>(), values.len());
        Self {
            name: name.into(),
            dtype: Dtype::F32,
            shape: shape.to_vec(),
            bytes: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }

    /// A rank-1 `u32` array.
    pub(super) fn u32(name: &str, values: &[u32]) -> Self {
        Self {
            name: name.into(),
            dtype: Dtype::U32,
            shape: vec![values.len()],
            bytes: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }

    /// A rank-1 `u8` array.
    pub(super) fn u8(name: &str, values: &[u8]) -> Self {
        Self {
            name: name.into(),
            dtype: Dtype::U8,
            shape: vec![values.len()],
            bytes: values.to_vec(),
        }
    }
}

/// Alignment of every field's data in a written file, bytes.
const DATA_ALIGNMENT: usize = 8;

/// The bytes of a tensor file (version 1.0) holding `fields` in order.
pub(super) fn encode(fields: &[FieldData]) -> Vec<u8> {
    let header_len = MAGIC.len()
        + 2
        + 4
        + fields
            .iter()
            .map(|f| 2 + f.name.len() + 2 + 1 + 8 + 8 * f.shape.len())
            .sum::<usize>();
    let align = |at: usize| at.div_ceil(DATA_ALIGNMENT) * DATA_ALIGNMENT;
    let mut offsets = Vec::with_capacity(fields.len());
    let mut end = align(header_len);
    for f in fields {
        offsets.push(end);
        end = align(end + f.bytes.len());
    }
    let mut out = Vec::with_capacity(end);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(fields.len() as u32).to_le_bytes());
    for (f, offset) in fields.iter().zip(&offsets) {
        out.extend_from_slice(&(f.name.len() as u16).to_le_bytes());
        out.extend_from_slice(f.name.as_bytes());
        out.extend_from_slice(&(f.shape.len() as u16).to_le_bytes());
        out.push(f.dtype.code());
        out.extend_from_slice(&(*offset as u64).to_le_bytes());
        for d in &f.shape {
            out.extend_from_slice(&(*d as u64).to_le_bytes());
        }
    }
    for (f, offset) in fields.iter().zip(&offsets) {
        out.resize(*offset, 0);
        out.extend_from_slice(&f.bytes);
    }
    out.resize(end, 0);
    out
}

/// A parsed tensor file: the field table over the file's bytes.
pub(super) struct TensorFile<'a> {
    bytes: &'a [u8],
    fields: HashMap<String, Field>,
}

/// A bounds-checked little-endian reader over the header.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], Malformed> {
        let end = self
            .at
            .checked_add(n)
            .filter(|end| *end <= self.bytes.len());
        match end {
            Some(end) => {
                let slice = &self.bytes[self.at..end];
                self.at = end;
                Ok(slice)
            }
            None => Err(format!(
                "truncated header: {what} at byte {} runs past the end of the file ({} bytes)",
                self.at,
                self.bytes.len()
            )
            .into()),
        }
    }

    fn u8(&mut self, what: &str) -> Result<u8, Malformed> {
        Ok(self.take(1, what)?[0])
    }

    fn u16(&mut self, what: &str) -> Result<u16, Malformed> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    fn u32(&mut self, what: &str) -> Result<u32, Malformed> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self, what: &str) -> Result<u64, Malformed> {
        let b = self.take(8, what)?;
        Ok(u64::from_le_bytes([
            b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7],
        ]))
    }
}

impl<'a> TensorFile<'a> {
    /// Parses the field table, checking the magic, the version and that every field's data
    /// lies inside the file. The error says what is wrong.
    pub(super) fn parse(bytes: &'a [u8]) -> Result<Self, Malformed> {
        if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
            return Err("not a tensor file (the first 12 bytes are not \"tensor_file\\0\")".into());
        }
        let mut cursor = Cursor {
            bytes,
            at: MAGIC.len(),
        };
        let version = [cursor.u8("version")?, cursor.u8("version")?];
        if version != [1, 0] {
            return Err(format!(
                "unsupported tensor file version {}.{} (expected 1.0)",
                version[0], version[1]
            )
            .into());
        }
        let count = cursor.u32("field count")?;
        let left = bytes.len() - cursor.at;
        if count as usize > left / MIN_FIELD_ENTRY_BYTES {
            return Err(format!(
                "truncated header: it claims {count} fields, more than its remaining {left} bytes can hold"
            )
            .into());
        }
        let mut fields = HashMap::new();
        for index in 0..count {
            let (name, field) = Self::parse_field(&mut cursor, index)?;
            if fields.insert(name.clone(), field).is_some() {
                return Err(format!("field '{name}' appears twice").into());
            }
        }
        Ok(Self { bytes, fields })
    }

    fn parse_field(cursor: &mut Cursor<'a>, index: u32) -> Result<(String, Field), Malformed> {
        let name_len = cursor.u16("field name length")? as usize;
        if name_len > MAX_FIELD_NAME_BYTES {
            return Err(format!(
                "field #{index} claims a name of {name_len} bytes, more than the {MAX_FIELD_NAME_BYTES} a field name may hold"
            )
            .into());
        }
        let raw_name = cursor.take(name_len, "field name")?;
        let name = match std::str::from_utf8(raw_name) {
            Ok(name) if !name.chars().any(char::is_control) => name.to_string(),
            _ => {
                return Err(format!(
                    "field #{index} has a name that is not printable text: '{}'",
                    specula_core::shown::excerpt_bytes(raw_name)
                )
                .into())
            }
        };
        let rank = cursor.u16("field rank")? as usize;
        if rank > MAX_RANK {
            return Err(format!(
                "field '{name}' claims rank {rank}, more than the {MAX_RANK} a field may have"
            )
            .into());
        }
        let code = cursor.u8("field dtype")?;
        let dtype = Dtype::from_code(code)
            .ok_or_else(|| format!("field '{name}' (#{index}) has unknown dtype code {code}"))?;
        let offset = cursor.u64("field offset")?;
        let mut shape = Vec::with_capacity(rank);
        for _ in 0..rank {
            shape.push(cursor.u64("field shape")?);
        }
        let file_len = cursor.bytes.len() as u64;
        let data_len = shape
            .iter()
            .try_fold(dtype.size_bytes() as u64, |acc, d| acc.checked_mul(*d))
            .ok_or_else(|| format!("field '{name}' has an impossible shape {shape:?}"))?;
        let end = offset.checked_add(data_len).filter(|end| *end <= file_len);
        if end.is_none() {
            return Err(format!(
                "truncated: field '{name}' ({dtype:?}{shape:?}) needs bytes {offset}..{} but the file has {file_len}",
                offset.saturating_add(data_len)
            ).into());
        }
        let field = Field {
            dtype,
            shape: shape.iter().map(|d| *d as usize).collect(),
            data_start: offset as usize,
            data_len: data_len as usize,
        };
        Ok((name, field))
    }

    /// The field called `name`, or an error naming it.
    pub(super) fn field(&self, name: &str) -> Result<&Field, Malformed> {
        self.fields
            .get(name)
            .ok_or_else(|| Malformed(format!("missing field '{name}'")))
    }

    /// The raw bytes of a field.
    fn data(&self, field: &Field) -> &'a [u8] {
        &self.bytes[field.data_start..field.data_start + field.data_len]
    }

    /// The elements of an `f32` field of the given rank, with its shape; every value must be
    /// finite.
    pub(super) fn f32_field(
        &self,
        name: &str,
        rank: usize,
    ) -> Result<(Vec<f32>, Vec<usize>), Malformed> {
        let field = self.field(name)?;
        if field.dtype != Dtype::F32 || field.shape.len() != rank {
            return Err(format!(
                "field '{name}' is {:?}{:?}, expected a rank-{rank} f32 array",
                field.dtype, field.shape
            )
            .into());
        }
        let values: Vec<f32> = self
            .data(field)
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        if let Some(pos) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "field '{name}' holds a non-finite value ({}) at element {pos}",
                values[pos]
            )
            .into());
        }
        Ok((values, field.shape.clone()))
    }

    /// The bytes of a rank-1 `u8` field.
    pub(super) fn u8_field(&self, name: &str) -> Result<&'a [u8], Malformed> {
        let field = self.field(name)?;
        if field.dtype != Dtype::U8 || field.shape.len() != 1 {
            return Err(format!(
                "field '{name}' is {:?}{:?}, expected a rank-1 u8 array",
                field.dtype, field.shape
            )
            .into());
        }
        Ok(self.data(field))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tensor file with the given fields `(name, dtype code, shape, data)`.
    fn build(fields: &[(&str, u8, Vec<u64>, Vec<u8>)]) -> Vec<u8> {
        let mut header = MAGIC.to_vec();
        header.extend_from_slice(&[1, 0]);
        header.extend_from_slice(&(fields.len() as u32).to_le_bytes());
        let header_len: usize = header.len()
            + fields
                .iter()
                .map(|(n, _, s, _)| 2 + n.len() + 2 + 1 + 8 + 8 * s.len())
                .sum::<usize>();
        let mut data = Vec::new();
        for (name, code, shape, bytes) in fields {
            header.extend_from_slice(&(name.len() as u16).to_le_bytes());
            header.extend_from_slice(name.as_bytes());
            header.extend_from_slice(&(shape.len() as u16).to_le_bytes());
            header.push(*code);
            header.extend_from_slice(&((header_len + data.len()) as u64).to_le_bytes());
            for d in shape {
                header.extend_from_slice(&d.to_le_bytes());
            }
            data.extend_from_slice(bytes);
        }
        header.extend_from_slice(&data);
        header
    }

    fn f32_bytes(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    #[test]
    fn reads_fields_back() {
        let bytes = build(&[
            ("a", 10, vec![2, 2], f32_bytes(&[1.0, 2.0, 3.0, 4.0])),
            ("flag", 1, vec![1], vec![7]),
        ]);
        let tf = TensorFile::parse(&bytes).unwrap();
        let (a, shape) = tf.f32_field("a", 2).unwrap();
        assert_eq!(a, vec![1.0, 2.0, 3.0, 4.0]);
        assert_eq!(shape, vec![2, 2]);
        assert_eq!(tf.u8_field("flag").unwrap(), &[7]);
        assert!(tf.field("b").unwrap_err().contains("missing field 'b'"));
        assert!(tf
            .f32_field("flag", 1)
            .unwrap_err()
            .contains("expected a rank-1 f32"));
    }

    #[test]
    fn encoded_files_parse_back_aligned() {
        let bytes = encode(&[
            FieldData::u8("flag", &[1, 2, 3]),
            FieldData::f32("grid", &[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, -6.5]),
            FieldData::u32("version", &[1, 0]),
        ]);
        let tf = TensorFile::parse(&bytes).unwrap();
        assert_eq!(tf.u8_field("flag").unwrap(), &[1, 2, 3]);
        let (grid, shape) = tf.f32_field("grid", 2).unwrap();
        assert_eq!(grid, vec![1.0, 2.0, 3.0, 4.0, 5.0, -6.5]);
        assert_eq!(shape, vec![2, 3]);
        let version = tf.field("version").unwrap();
        assert_eq!(
            (version.dtype, version.shape.clone()),
            (Dtype::U32, vec![2])
        );
        assert!(tf
            .fields
            .values()
            .all(|f| f.data_start % DATA_ALIGNMENT == 0));
        for code in 1..=11 {
            assert_eq!(Dtype::from_code(code).unwrap().code(), code);
        }
    }

    #[test]
    fn bad_containers_are_described() {
        assert!(TensorFile::parse(b"tensor_fil").is_err());
        assert!(TensorFile::parse(b"MERL........xx")
            .err()
            .unwrap()
            .contains("not a tensor file"));
        let good = build(&[("a", 10, vec![3], f32_bytes(&[1.0, f32::NAN, 3.0]))]);
        let err = TensorFile::parse(&good[..good.len() - 1]).err().unwrap();
        assert!(err.contains("truncated"), "{err}");
        let err = TensorFile::parse(&good[..20]).err().unwrap();
        assert!(err.contains("truncated header"), "{err}");
        let tf = TensorFile::parse(&good).unwrap();
        assert!(tf.f32_field("a", 1).unwrap_err().contains("non-finite"));
        let mut version = good.clone();
        version[12] = 2;
        assert!(TensorFile::parse(&version)
            .err()
            .unwrap()
            .contains("version 2.0"));
        let huge = build(&[("a", 10, vec![u64::MAX, 4], vec![])]);
        assert!(TensorFile::parse(&huge)
            .err()
            .unwrap()
            .contains("impossible shape"));
        let big = build(&[("a", 10, vec![1 << 40], vec![])]);
        assert!(TensorFile::parse(&big)
            .err()
            .unwrap()
            .contains("truncated: field 'a'"));
        let dtype = build(&[("a", 42, vec![1], vec![0])]);
        assert!(TensorFile::parse(&dtype)
            .err()
            .unwrap()
            .contains("unknown dtype code 42"));
    }

    #[test]
    fn length_fields_are_bounded_and_errors_quote_little() {
        // A field whose name claims 65535 bytes of what follows, escape bytes included.
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&[1, 0]);
        bytes.extend_from_slice(&1u32.to_le_bytes());
        bytes.extend_from_slice(&u16::MAX.to_le_bytes());
        bytes.extend(std::iter::repeat_n(0x1b, 120_000));
        let err = TensorFile::parse(&bytes).err().unwrap();
        assert_eq!(
            err.0,
            "field #0 claims a name of 65535 bytes, more than the 64 a field name may hold"
        );
        let escape = build(&[("a\x1b[2J\nb", 10, vec![1], f32_bytes(&[1.0]))]);
        let err = TensorFile::parse(&escape).err().unwrap();
        assert!(
            err.contains("not printable text: 'a\\u{1b}[2J\\nb'"),
            "{err}"
        );
        let mut rank = build(&[("a", 10, vec![1], f32_bytes(&[1.0]))]);
        let at = MAGIC.len() + 2 + 4 + 2 + 1;
        rank[at..at + 2].copy_from_slice(&u16::MAX.to_le_bytes());
        let err = TensorFile::parse(&rank).err().unwrap();
        assert!(err.contains("claims rank 65535"), "{err}");
        let mut count = build(&[("a", 10, vec![1], f32_bytes(&[1.0]))]);
        count[14..18].copy_from_slice(&u32::MAX.to_le_bytes());
        let err = TensorFile::parse(&count).err().unwrap();
        assert!(err.contains("claims 4294967295 fields"), "{err}");
        assert!(err.starts_with("truncated header"), "{err}");
    }
}
