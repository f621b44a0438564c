#!/usr/bin/env python3
"""Voxelizes a textured triangle mesh (glTF, OBJ, PLY...) into a MagicaVoxel file.

The blocky mesher's bench and peer tests read `.vox` files from `BLOCKY_VOX_DIR`. Models
voxelized from textured meshes are a class of their own: a surface whose colours come from
a texture, quantized to a palette, so neighbouring voxels often differ in id by one shade.
This writes such models from any mesh `trimesh` loads:

    scripts/voxelize-mesh.py ../shared/data/gltf/Duck.glb duck_solid_250.vox 250 --fill
    BLOCKY_VOX_DIR=<folder> BLOCKY_INPUTS=vox/ BLOCKY_CRITERION=0 \\
        cargo bench -p benches --bench blocky
    BLOCKY_VOX_DIR=<folder> cargo test --release -p tests --test blocky_peers

How: the mesh (every node with its transform) is scaled so that its longest side spans
`edge` voxels exactly; points are sampled on its surface, about 12 per voxel face of area; each
voxel a point lands in is solid, coloured from the texture at the point's texture
coordinates (or the material's colour, or the face colours) by the first point that lands
in it. `--fill` also fills the enclosed interior, in one colour. The colours are quantized
to `--colours` palette entries (median cut), written as a 255-entry `RGBA` chunk. Mesh +y
becomes MagicaVoxel's +z (up). One model, so `edge` is at most 256.

Needs `trimesh`, `numpy`, `pillow` and, for `--fill`, `scipy` (`pip install trimesh numpy
pillow scipy`).
"""

import argparse
import struct

import numpy as np
import trimesh
from PIL import Image

# Surface samples per voxel face of area: enough that every voxel the surface passes
# through gets one.
SAMPLES_PER_FACE = 12

# The colour of the filled interior (never seen from outside).
INTERIOR = (120, 100, 80)


def meshes_of(path):
    """Every mesh of the file, with its node's transform applied."""
    try:
        scene = trimesh.load(path, force="scene")
    except Exception as error:  # trimesh raises many kinds; each names the problem
        raise SystemExit(f"{path}: cannot load: {error}") from error
    meshes = []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        mesh = scene.geometry[name].copy()
        mesh.apply_transform(transform)
        meshes.append(mesh)
    if not meshes:
        raise SystemExit(f"{path}: no mesh in the file")
    return meshes


def colours_at(mesh, faces, points):
    """RGB of each point (on face `faces[i]`): texture, material colour or face colour."""
    visual = mesh.visual
    if isinstance(visual, trimesh.visual.texture.TextureVisuals):
        material = visual.material
        image = getattr(material, "baseColorTexture", None) or getattr(material, "image", None)
        if image is not None and visual.uv is not None:
            corners = mesh.triangles[faces]
            weights = trimesh.triangles.points_to_barycentric(corners, points)
            uv = (visual.uv[mesh.faces[faces]] * weights[:, :, None]).sum(axis=1)
            texels = np.asarray(image.convert("RGB"))
            height, width = texels.shape[:2]
            u, v = np.mod(uv[:, 0], 1.0), np.mod(uv[:, 1], 1.0)
            px = np.clip((u * width).astype(int), 0, width - 1)
            py = np.clip(((1 - v) * height).astype(int), 0, height - 1)
            return texels[py, px]
        factor = getattr(material, "baseColorFactor", None)
        colour = np.array(factor[:3] if factor is not None else (200, 200, 200))
        return np.tile(colour, (len(points), 1))
    return visual.face_colors[faces, :3]


def chunk(tag, content):
    """A MagicaVoxel chunk without children."""
    return tag + struct.pack("<ii", len(content), 0) + content


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh", help="the mesh file (glTF, OBJ, PLY, STL...)")
    parser.add_argument("out", help="the .vox file to write")
    parser.add_argument("edge", type=int, help="voxels along the longest side, 2 to 256")
    parser.add_argument("--fill", action="store_true", help="fill the enclosed interior")
    parser.add_argument("--colours", type=int, default=255, help="palette entries, 1 to 255")
    args = parser.parse_args()
    if not 2 <= args.edge <= 256:
        raise SystemExit(f"edge {args.edge}: one MagicaVoxel model spans 2 to 256 voxels")
    if not 1 <= args.colours <= 255:
        raise SystemExit(f"--colours {args.colours}: a palette has 1 to 255 entries")

    meshes = meshes_of(args.mesh)
    low = np.min([m.bounds[0] for m in meshes], axis=0)
    high = np.max([m.bounds[1] for m in meshes], axis=0)
    pitch = (high - low).max() / args.edge
    if not np.isfinite(pitch) or pitch <= 0:
        raise SystemExit(
            f"{args.mesh}: the mesh has no extent (every vertex at one point); a file with "
            "Draco-compressed meshes needs `pip install DracoPy`"
        )
    points, colours = [], []
    for mesh in meshes:
        count = int(mesh.area / pitch**2 * SAMPLES_PER_FACE) + 1000
        at, faces = trimesh.sample.sample_surface(mesh, count, seed=1)
        points.append(at)
        colours.append(colours_at(mesh, faces, at))
    points = np.concatenate(points)
    colours = np.concatenate(colours).astype(np.uint8)

    # A point on the far side of the bounds (at `low + edge * pitch`) lies on the boundary of
    # the last voxel, not in a voxel past it.
    cells = np.minimum(np.floor((points - low) / pitch).astype(int), args.edge - 1)
    dims = cells.max(axis=0) + 1
    keys = cells[:, 0] + dims[0] * (cells[:, 1] + dims[1] * cells[:, 2])
    _, first = np.unique(keys, return_index=True)
    solid = np.zeros(dims, bool)
    solid[tuple(cells[first].T)] = True
    rgb = np.zeros((*dims, 3), np.uint8)
    rgb[tuple(cells[first].T)] = colours[first]
    if args.fill:
        from scipy import ndimage

        filled = ndimage.binary_fill_holes(solid)
        rgb[filled & ~solid] = INTERIOR
        solid = filled

    voxels = np.argwhere(solid)
    quantized = Image.fromarray(rgb[tuple(voxels.T)].reshape(1, -1, 3)).quantize(
        colors=args.colours, method=Image.Quantize.MEDIANCUT
    )
    indexes = np.asarray(quantized).reshape(-1).astype(np.uint8) + 1
    palette = np.array(quantized.getpalette()[: 3 * args.colours], np.uint8).reshape(-1, 3)
    palette = np.vstack([palette, np.zeros((255 - len(palette), 3), np.uint8)])

    # Mesh +y up becomes MagicaVoxel's +z up.
    x, y, z = voxels[:, 0], voxels[:, 2], voxels[:, 1]
    size = struct.pack("<iii", dims[0], dims[2], dims[1])
    xyzi = struct.pack("<i", len(voxels)) + np.stack([x, y, z, indexes], 1).astype(np.uint8).tobytes()
    rgba = np.hstack([palette, np.full((255, 1), 255, np.uint8)]).tobytes()
    body = chunk(b"SIZE", size) + chunk(b"XYZI", xyzi) + chunk(b"RGBA", rgba)
    with open(args.out, "wb") as out:
        out.write(b"VOX " + struct.pack("<i", 150) + b"MAIN" + struct.pack("<ii", 0, len(body)))
        out.write(body)
    print(f"{args.out}: {dims[0]} x {dims[2]} x {dims[1]} voxels (x, y, z up), {len(voxels)} solid")


if __name__ == "__main__":
    main()
