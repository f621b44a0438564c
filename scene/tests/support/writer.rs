//! A small `.vox` writer for tests: valid files with any chunk the loader reads, and, by
//! writing raw chunks or editing the bytes afterwards, every kind of malformed file.
//!
//! Shared by the scene crate's tests, voxmesh's tests and the fuzz seed corpus (included with
//! `#[path]`), so it uses only `std`.

#![allow(
    dead_code,
    reason = "each including test uses a different part of the writer"
)]

/// The chunks of a file under construction, in order.
#[derive(Clone, Debug, Default)]
pub(crate) struct VoxWriter {
    chunks: Vec<([u8; 4], Vec<u8>)>,
}

/// A dictionary: a count and key-value strings.
pub(crate) fn dict(pairs: &[(&str, &str)]) -> Vec<u8> {
    let mut out = (pairs.len() as u32).to_le_bytes().to_vec();
    for (k, v) in pairs {
        out.extend(string(k));
        out.extend(string(v));
    }
    out
}

/// A string: a length and the bytes.
pub(crate) fn string(s: &str) -> Vec<u8> {
    let mut out = (s.len() as u32).to_le_bytes().to_vec();
    out.extend_from_slice(s.as_bytes());
    out
}

fn i32s(values: &[i32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

impl VoxWriter {
    /// An empty file (just `VOX `, the version and an empty `MAIN`).
    pub(crate) fn new() -> VoxWriter {
        VoxWriter::default()
    }

    /// Appends a raw chunk.
    pub(crate) fn chunk(&mut self, id: &[u8; 4], content: Vec<u8>) -> &mut Self {
        self.chunks.push((*id, content));
        self
    }

    /// Appends a `SIZE` and an `XYZI` chunk: a model of `size` with `voxels` (x, y, z,
    /// colour index), the count written truthfully.
    pub(crate) fn model(&mut self, size: [i32; 3], voxels: &[[u8; 4]]) -> &mut Self {
        self.chunk(b"SIZE", i32s(&size));
        let mut xyzi = (voxels.len() as u32).to_le_bytes().to_vec();
        xyzi.extend(voxels.iter().flatten());
        self.chunk(b"XYZI", xyzi)
    }

    /// Appends an `RGBA` palette: entry `i` is colour index `i + 1`.
    pub(crate) fn palette(&mut self, colours: &[[u8; 4]; 256]) -> &mut Self {
        self.chunk(b"RGBA", colours.iter().flatten().copied().collect())
    }

    /// Appends a `MATL` chunk for colour index `id`.
    pub(crate) fn matl(&mut self, id: i32, properties: &[(&str, &str)]) -> &mut Self {
        let mut content = i32s(&[id]);
        content.extend(dict(properties));
        self.chunk(b"MATL", content)
    }

    /// Appends an `nTRN` node with one frame.
    pub(crate) fn transform(
        &mut self,
        id: i32,
        attributes: &[(&str, &str)],
        child: i32,
        layer: i32,
        frame: &[(&str, &str)],
    ) -> &mut Self {
        self.transform_frames(id, attributes, child, layer, &[frame])
    }

    /// Appends an `nTRN` node with any number of frames.
    pub(crate) fn transform_frames(
        &mut self,
        id: i32,
        attributes: &[(&str, &str)],
        child: i32,
        layer: i32,
        frames: &[&[(&str, &str)]],
    ) -> &mut Self {
        let mut content = i32s(&[id]);
        content.extend(dict(attributes));
        content.extend(i32s(&[child, -1, layer, frames.len() as i32]));
        for frame in frames {
            content.extend(dict(frame));
        }
        self.chunk(b"nTRN", content)
    }

    /// Appends an `nGRP` node.
    pub(crate) fn group(
        &mut self,
        id: i32,
        attributes: &[(&str, &str)],
        children: &[i32],
    ) -> &mut Self {
        let mut content = i32s(&[id]);
        content.extend(dict(attributes));
        content.extend(i32s(&[children.len() as i32]));
        content.extend(i32s(children));
        self.chunk(b"nGRP", content)
    }

    /// Appends an `nSHP` node showing `models` (one per animation keyframe).
    pub(crate) fn shape(
        &mut self,
        id: i32,
        attributes: &[(&str, &str)],
        models: &[i32],
    ) -> &mut Self {
        let mut content = i32s(&[id]);
        content.extend(dict(attributes));
        content.extend(i32s(&[models.len() as i32]));
        for (frame, model) in models.iter().enumerate() {
            content.extend(i32s(&[*model]));
            let f = frame.to_string();
            content.extend(dict(&[("_f", f.as_str())]));
        }
        self.chunk(b"nSHP", content)
    }

    /// Appends a `LAYR` chunk.
    pub(crate) fn layer(&mut self, id: i32, attributes: &[(&str, &str)]) -> &mut Self {
        let mut content = i32s(&[id]);
        content.extend(dict(attributes));
        content.extend(i32s(&[-1]));
        self.chunk(b"LAYR", content)
    }

    /// The file's bytes: header, `MAIN`, then the chunks.
    pub(crate) fn bytes(&self) -> Vec<u8> {
        let mut children = Vec::new();
        for (id, content) in &self.chunks {
            children.extend_from_slice(id);
            children.extend((content.len() as u32).to_le_bytes());
            children.extend(0u32.to_le_bytes());
            children.extend(content);
        }
        let mut out = b"VOX ".to_vec();
        out.extend(200u32.to_le_bytes());
        out.extend_from_slice(b"MAIN");
        out.extend(0u32.to_le_bytes());
        out.extend((children.len() as u32).to_le_bytes());
        out.extend(children);
        out
    }

    /// Byte offset of chunk `index`'s header in [`bytes`](Self::bytes).
    pub(crate) fn offset_of(&self, index: usize) -> usize {
        20 + self.chunks[..index]
            .iter()
            .map(|(_, c)| 12 + c.len())
            .sum::<usize>()
    }

    /// Number of chunks so far.
    pub(crate) fn len(&self) -> usize {
        self.chunks.len()
    }
}

/// A scene of two models under a group, each with its own transform, plus a palette:
/// model 0 (2 x 2 x 1, index 1-4) at `(-3, 0, 0)`, model 1 (1 x 1 x 3, index 5) at
/// `(4, 2, 1)`, rotated by `_r = 17`.
pub(crate) fn two_model_scene() -> VoxWriter {
    let mut w = VoxWriter::new();
    w.model(
        [2, 2, 1],
        &[[0, 0, 0, 1], [1, 0, 0, 2], [0, 1, 0, 3], [1, 1, 0, 4]],
    )
    .model([1, 1, 3], &[[0, 0, 0, 5], [0, 0, 1, 5], [0, 0, 2, 5]])
    .transform(0, &[], 1, -1, &[])
    .group(1, &[], &[2, 4])
    .transform(2, &[("_name", "left")], 3, 0, &[("_t", "-3 0 0")])
    .shape(3, &[], &[0])
    .transform(4, &[], 5, 0, &[("_t", "4 2 1"), ("_r", "17")])
    .shape(5, &[], &[1])
    .layer(0, &[("_name", "main")]);
    let colours = std::array::from_fn(|i| [i as u8, 255 - i as u8, 7, 255]);
    w.palette(&colours);
    w
}
