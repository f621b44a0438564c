//! Takes a GLB apart into its JSON (as a `serde_json::Value`) and BIN chunk and puts it back
//! together, so a test can break one thing of a real sample.

#![allow(dead_code, reason = "each including test uses a different part")]

use serde_json::Value;

/// A GLB file as JSON and BIN, to edit.
pub(crate) struct Glb {
    /// The JSON chunk, parsed.
    pub(crate) json: Value,
    /// The BIN chunk.
    pub(crate) bin: Option<Vec<u8>>,
}

fn u32_at(b: &[u8], at: usize) -> usize {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap()) as usize
}

impl Glb {
    /// Splits a valid GLB file.
    pub(crate) fn parse(bytes: &[u8]) -> Glb {
        assert_eq!(&bytes[..4], b"glTF");
        let json_len = u32_at(bytes, 12);
        let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        let at = 20 + json_len;
        let bin = (at < bytes.len()).then(|| {
            let len = u32_at(bytes, at);
            bytes[at + 8..at + 8 + len].to_vec()
        });
        Glb { json, bin }
    }

    /// The GLB file: header, JSON chunk padded with spaces, BIN chunk padded with zeros.
    pub(crate) fn bytes(&self) -> Vec<u8> {
        let mut json = serde_json::to_vec(&self.json).unwrap();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(0u32.to_le_bytes());
        out.extend((json.len() as u32).to_le_bytes());
        out.extend(0x4E4F_534Au32.to_le_bytes());
        out.extend(&json);
        if let Some(bin) = &self.bin {
            let mut bin = bin.clone();
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            out.extend((bin.len() as u32).to_le_bytes());
            out.extend(0x004E_4942u32.to_le_bytes());
            out.extend(&bin);
        }
        let len = out.len() as u32;
        out[8..12].copy_from_slice(&len.to_le_bytes());
        out
    }

    /// Byte offset in BIN of element `element` of accessor `accessor` (tightly packed or
    /// strided by its view).
    pub(crate) fn element_offset(&self, accessor: usize, element: usize, size: usize) -> usize {
        let a = &self.json["accessors"][accessor];
        let view = &self.json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        let stride = view["byteStride"].as_u64().map_or(size, |s| s as usize);
        view["byteOffset"].as_u64().unwrap_or(0) as usize
            + a["byteOffset"].as_u64().unwrap_or(0) as usize
            + element * stride
    }
}
