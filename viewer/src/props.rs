//! glTF props over the streamed terrain: `--prop FILE@X,Y,Z[,SCALE]` places one model,
//! `--scatter FILE:COUNT` places `COUNT` instances on the terrain surface (a fixed seed, so
//! every run places them alike). The loader's warnings are printed; a bad flag, an unreadable
//! or malformed file, or a position outside the world is refused by name.

use std::fmt;
use std::path::PathBuf;

use glam::DVec3;
use gpu_backend::render::Renderer;
use gpu_backend::render::props::PropError;
use render_model::props::{PlacementError, PropPlacement};
use voxel_scene::Terrain;
use voxel_scene::props::{PropError as LoadError, PropLimits, PropModel, load_prop_file};

/// `--prop FILE@X,Y,Z[,SCALE]`.
#[derive(Clone, Debug, PartialEq)]
pub struct PropFlag {
    /// The glTF or GLB file.
    pub file: PathBuf,
    /// World position of the model's origin, blocks.
    pub position: [f64; 3],
    /// Uniform scale (1 unless given).
    pub scale: f64,
}

/// `--scatter FILE:COUNT`.
#[derive(Clone, Debug, PartialEq)]
pub struct ScatterFlag {
    /// The glTF or GLB file.
    pub file: PathBuf,
    /// Instances placed.
    pub count: u32,
}

/// Parses `FILE@X,Y,Z[,SCALE]` (finite numbers, a positive scale).
pub fn parse_prop(text: &str) -> Result<PropFlag, String> {
    let bad = |why: &str| format!("prop `{text}`: {why} (expected FILE@X,Y,Z[,SCALE])");
    let (file, rest) = text.rsplit_once('@').ok_or_else(|| bad("no @"))?;
    if file.is_empty() {
        return Err(bad("no file"));
    }
    let numbers = rest
        .split(',')
        .map(|s| s.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| bad("not a finite number"))?;
    let (position, scale) = match numbers[..] {
        [x, y, z] => ([x, y, z], 1.0),
        [x, y, z, s] => ([x, y, z], s),
        _ => return Err(bad("three or four numbers")),
    };
    if scale <= 0.0 {
        return Err(bad("the scale must be positive"));
    }
    Ok(PropFlag {
        file: PathBuf::from(file),
        position,
        scale,
    })
}

/// Parses `FILE:COUNT` (1 to 10,000,000).
pub fn parse_scatter(text: &str) -> Result<ScatterFlag, String> {
    let bad = |why: &str| format!("scatter `{text}`: {why} (expected FILE:COUNT)");
    let (file, count) = text.rsplit_once(':').ok_or_else(|| bad("no :"))?;
    if file.is_empty() {
        return Err(bad("no file"));
    }
    let count: u32 = count
        .parse()
        .map_err(|_| bad("COUNT is not a whole number"))?;
    if !(1..=10_000_000).contains(&count) {
        return Err(bad("COUNT must be 1 to 10000000"));
    }
    Ok(ScatterFlag {
        file: PathBuf::from(file),
        count,
    })
}

/// Models and where their instances go.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PropScene {
    /// The loaded models.
    pub models: Vec<PropModel>,
    /// Per instance: its model and placement.
    pub placements: Vec<(usize, PropPlacement)>,
}

/// Why the props could not be set up.
#[derive(Debug)]
pub enum PropSceneError {
    /// A file could not be loaded.
    Load(PathBuf, LoadError),
    /// A position is outside the world.
    Placement(PathBuf, PlacementError),
    /// The renderer refused a model or an instance.
    Renderer(PropError),
}

impl fmt::Display for PropSceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PropSceneError::Load(p, e) => write!(f, "prop {}: {e}", p.display()),
            PropSceneError::Placement(p, e) => write!(f, "prop {}: {e:?}", p.display()),
            PropSceneError::Renderer(e) => write!(f, "props: {e}"),
        }
    }
}

impl std::error::Error for PropSceneError {}

fn scaled(scale: f64) -> [[f32; 4]; 4] {
    let s = scale as f32;
    [
        [s, 0.0, 0.0, 0.0],
        [0.0, s, 0.0, 0.0],
        [0.0, 0.0, s, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// Scatter positions: a square of half width `radius` around the origin, SplitMix64 from a
/// fixed seed.
fn scatter_points(count: u32, radius: f64) -> impl Iterator<Item = (f64, f64)> {
    let mut state = 0x005e_ed0f_0905_u64;
    let mut next = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..count).map(move |_| ((next() * 2.0 - 1.0) * radius, (next() * 2.0 - 1.0) * radius))
}

/// Loads the files of the flags (printing their warnings) and places the instances; scattered
/// ones stand on `terrain`'s surface within `radius` blocks of the origin.
pub fn prop_scene(
    props: &[PropFlag],
    scatters: &[ScatterFlag],
    terrain: &Terrain,
    radius: f64,
) -> Result<PropScene, PropSceneError> {
    let mut scene = PropScene::default();
    let load = |file: &PathBuf, scene: &mut PropScene| -> Result<usize, PropSceneError> {
        let model = load_prop_file(file, &PropLimits::default())
            .map_err(|e| PropSceneError::Load(file.clone(), e))?;
        for w in &model.warnings {
            eprintln!("viewer: prop {}: warning: {w}", file.display());
        }
        scene.models.push(model);
        Ok(scene.models.len() - 1)
    };
    for p in props {
        let m = load(&p.file, &mut scene)?;
        let at = PropPlacement::at_world(DVec3::from_array(p.position), scaled(p.scale))
            .map_err(|e| PropSceneError::Placement(p.file.clone(), e))?;
        scene.placements.push((m, at));
    }
    for s in scatters {
        let m = load(&s.file, &mut scene)?;
        for (x, z) in scatter_points(s.count, radius) {
            let y = f64::from(terrain.height(x.floor() as i32, z.floor() as i32) + 1);
            let at = PropPlacement::at_world(DVec3::new(x, y, z), scaled(1.0))
                .map_err(|e| PropSceneError::Placement(s.file.clone(), e))?;
            scene.placements.push((m, at));
        }
    }
    Ok(scene)
}

/// Adds `scene`'s models and instances to `renderer`.
pub fn add_props(renderer: &mut Renderer, scene: &PropScene) -> Result<(), PropSceneError> {
    let ids = scene
        .models
        .iter()
        .map(|m| renderer.add_prop_model(m))
        .collect::<Result<Vec<_>, _>>()
        .map_err(PropSceneError::Renderer)?;
    for (m, at) in &scene.placements {
        renderer
            .create_prop(ids[*m], *at)
            .map_err(PropSceneError::Renderer)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_parse_and_bad_ones_are_named() {
        let p = parse_prop("a/Duck.glb@1,2.5,-3").unwrap();
        assert_eq!(p.position, [1.0, 2.5, -3.0]);
        assert_eq!(p.scale, 1.0);
        assert_eq!(parse_prop("d.glb@0,0,0,2").unwrap().scale, 2.0);
        for bad in [
            "d.glb",
            "@1,2,3",
            "d.glb@1,2",
            "d.glb@1,2,x",
            "d.glb@1,2,3,0",
            "d.glb@1,2,inf",
        ] {
            assert!(parse_prop(bad).unwrap_err().contains("prop"), "{bad}");
        }
        assert_eq!(parse_scatter("d.glb:10").unwrap().count, 10);
        for bad in ["d.glb", ":3", "d.glb:0", "d.glb:-1", "d.glb:x"] {
            assert!(parse_scatter(bad).unwrap_err().contains("scatter"), "{bad}");
        }
    }

    #[test]
    fn scatter_is_deterministic_and_inside_the_square() {
        let a: Vec<_> = scatter_points(100, 50.0).collect();
        let b: Vec<_> = scatter_points(100, 50.0).collect();
        assert_eq!(a, b);
        assert!(a.iter().all(|(x, z)| x.abs() <= 50.0 && z.abs() <= 50.0));
        assert!(a.windows(2).all(|w| w[0] != w[1]));
    }

    #[test]
    fn a_missing_file_is_refused_by_name() {
        let terrain = Terrain::new(1, voxel_scene::TerrainBlocks::palette().1);
        let flag = parse_prop("/nonexistent/none.glb@0,0,0").unwrap();
        let err = prop_scene(&[flag], &[], &terrain, 10.0).unwrap_err();
        assert!(err.to_string().contains("none.glb"), "{err}");
    }
}
