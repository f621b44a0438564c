//! The WGSL twins of `render-model`'s records and constants: each `#[repr(C)]` record's size
//! and field offsets, and each shared constant, checked against naga's reflection of the
//! shader that reads it. The records live without wgpu; their twins live here with the
//! shaders, so this is where the two are compared.

mod cull {
    use std::mem::offset_of;

    use render_model::cull::*;

    use crate::shaders::{CULL, struct_layout, validate};

    /// The same bytes as wgpu's own indexed indirect arguments.
    fn draw_args_to_wgpu(args: DrawIndexedArgs) -> wgpu::util::DrawIndexedIndirectArgs {
        wgpu::util::DrawIndexedIndirectArgs {
            index_count: args.index_count,
            instance_count: args.instance_count,
            first_index: args.first_index,
            base_vertex: args.base_vertex,
            first_instance: args.first_instance,
        }
    }

    #[test]
    fn uniforms_match_the_wgsl_struct() {
        use std::mem::offset_of;
        let module = validate(CULL.name, &CULL.source()).unwrap_or_else(|e| panic!("{e}"));
        let (members, size) = struct_layout(&module, "CullUniforms");
        assert_eq!(size, size_of::<CullUniforms>());
        let expected = [
            ("planes", offset_of!(CullUniforms, planes)),
            ("camera_chunk", offset_of!(CullUniforms, camera_chunk)),
            ("layer", offset_of!(CullUniforms, layer)),
            ("camera_offset", offset_of!(CullUniforms, camera_offset)),
            ("chunk_edge", offset_of!(CullUniforms, chunk_edge)),
            ("slot_bound", offset_of!(CullUniforms, slot_bound)),
            ("page_count", offset_of!(CullUniforms, page_count)),
            ("page_capacity", offset_of!(CullUniforms, page_capacity)),
            (
                "last_page_capacity",
                offset_of!(CullUniforms, last_page_capacity),
            ),
            (
                "commands_per_page",
                offset_of!(CullUniforms, commands_per_page),
            ),
            (
                "max_quads_per_draw",
                offset_of!(CullUniforms, max_quads_per_draw),
            ),
            ("flags", offset_of!(CullUniforms, flags)),
            ("phase", offset_of!(CullUniforms, phase)),
            ("far_cell_px", offset_of!(CullUniforms, far_cell_px)),
            ("far_capacity", offset_of!(CullUniforms, far_capacity)),
            (
                "smooth_vertex_page_capacity",
                offset_of!(CullUniforms, smooth_vertex_page_capacity),
            ),
            (
                "smooth_quad_page_capacity",
                offset_of!(CullUniforms, smooth_quad_page_capacity),
            ),
            (
                "smooth_quad_pages",
                offset_of!(CullUniforms, smooth_quad_pages),
            ),
            (
                "smooth_commands_per_pair",
                offset_of!(CullUniforms, smooth_commands_per_pair),
            ),
            ("smooth_pairs", offset_of!(CullUniforms, smooth_pairs)),
            ("focal_px", offset_of!(CullUniforms, focal_px)),
            ("lod", offset_of!(CullUniforms, lod)),
            ("view_proj", offset_of!(CullUniforms, view_proj)),
            ("screen", offset_of!(CullUniforms, screen)),
            ("near", offset_of!(CullUniforms, near)),
            ("pad", offset_of!(CullUniforms, pad)),
        ];
        let got: Vec<(&str, usize)> = members.iter().map(|(n, o)| (n.as_str(), *o)).collect();
        assert_eq!(got, expected);
        let (members, size) = struct_layout(&module, "LodParams");
        assert_eq!(size, size_of::<LodParams>());
        let got: Vec<(&str, usize)> = members.iter().map(|(n, o)| (n.as_str(), *o)).collect();
        assert_eq!(
            got,
            [
                ("anchor_chunk", offset_of!(LodParams, anchor_chunk)),
                ("top_level", offset_of!(LodParams, top_level)),
                ("anchor_offset", offset_of!(LodParams, anchor_offset)),
                ("budget_px", offset_of!(LodParams, budget_px)),
                ("focal_px", offset_of!(LodParams, focal_px)),
                ("hysteresis", offset_of!(LodParams, hysteresis)),
                ("chunk_edge", offset_of!(LodParams, chunk_edge)),
                ("pad", offset_of!(LodParams, pad)),
            ]
        );
    }

    #[test]
    fn draw_args_match_the_wgsl_struct_and_wgpu() {
        let module = validate(CULL.name, &CULL.source()).unwrap_or_else(|e| panic!("{e}"));
        let (members, size) = struct_layout(&module, "DrawIndexedArgs");
        assert_eq!(size, 20);
        let offsets: Vec<usize> = members.iter().map(|m| m.1).collect();
        assert_eq!(offsets, [0, 4, 8, 12, 16]);
        let args = DrawIndexedArgs {
            index_count: 1,
            instance_count: 2,
            first_index: 3,
            base_vertex: -4,
            first_instance: 5,
        };
        assert_eq!(
            bytemuck::bytes_of(&args),
            draw_args_to_wgpu(args).as_bytes()
        );
        // The records repeat the args in their first 20 bytes.
        let record = ChunkDrawIndirect {
            index_count: 1,
            instance_count: 2,
            first_index: 3,
            base_vertex: -4,
            first_instance: 5,
            chunk: [0; 3],
        };
        assert_eq!(
            &bytemuck::bytes_of(&record)[..20],
            bytemuck::bytes_of(&args)
        );
        // cull.wgsl's write_record stores the fields as two vec4<u32> in this order.
        use std::mem::offset_of;
        use voxel_core::formats::ChunkDrawIndirect;
        assert_eq!(offset_of!(ChunkDrawIndirect, first_instance), 16);
        assert_eq!(offset_of!(ChunkDrawIndirect, chunk), 20);
        assert_eq!(size_of::<ChunkDrawIndirect>(), 32);
    }

    #[test]
    fn node_record_matches_its_wgsl_twin() {
        let module = validate(CULL.name, &CULL.source()).unwrap_or_else(|e| panic!("{e}"));
        let (members, size) = struct_layout(&module, "NodeRecord");
        assert_eq!(size, size_of::<NodeRecord>());
        let got: Vec<(&str, usize)> = members.iter().map(|(n, o)| (n.as_str(), *o)).collect();
        assert_eq!(
            got,
            [
                (
                    "smooth_quad_offset",
                    offset_of!(NodeRecord, smooth_quad_offset)
                ),
                (
                    "smooth_quad_count",
                    offset_of!(NodeRecord, smooth_quad_count)
                ),
                ("smooth_quad_form", offset_of!(NodeRecord, smooth_quad_form)),
                ("block_offset", offset_of!(NodeRecord, block_offset)),
                ("block_count", offset_of!(NodeRecord, block_count)),
                ("mask_offset", offset_of!(NodeRecord, mask_offset)),
                ("mask_words", offset_of!(NodeRecord, mask_words)),
                ("flags", offset_of!(NodeRecord, flags)),
                ("opaque_skirts", offset_of!(NodeRecord, opaque_skirts)),
                ("block_skirts", offset_of!(NodeRecord, block_skirts)),
                ("shell_offset", offset_of!(NodeRecord, shell_offset)),
                ("shell_count", offset_of!(NodeRecord, shell_count)),
            ]
        );
    }

    #[test]
    fn shader_constants_match() {
        let source = CULL.source();
        assert!(source.contains(&format!("const ORDER_KEYS: u32 = {ORDER_KEYS}u;")));
        assert!(source.contains(&format!("const ORDER_KEY_BASE: u32 = {ORDER_KEY_BASE}u;")));
    }
}

mod frame {
    use std::mem::offset_of;

    use render_model::frame::{FrameUniforms, SmoothDraw};
    use render_model::lighting::LightingUniforms;

    use crate::shaders::{GBUFFER, LIGHTING, struct_layout, validate};

    fn check(module: &naga::Module, name: &str, size: usize, expected: &[(&str, usize)]) {
        let (members, span) = struct_layout(module, name);
        assert_eq!(span, size, "{name} size");
        let got: Vec<(&str, usize)> = members.iter().map(|(n, o)| (n.as_str(), *o)).collect();
        assert_eq!(got, expected, "{name} members");
    }

    #[test]
    fn uniforms_and_records_match_their_wgsl_twins() {
        for spec in [GBUFFER, LIGHTING] {
            let module = validate(spec.name, &spec.source()).unwrap_or_else(|e| panic!("{e}"));
            check(
                &module,
                "FrameUniforms",
                size_of::<FrameUniforms>(),
                &[
                    ("view_proj", offset_of!(FrameUniforms, view_proj)),
                    ("camera_offset", offset_of!(FrameUniforms, camera_offset)),
                    ("chunk_edge", offset_of!(FrameUniforms, chunk_edge)),
                    ("camera_chunk", offset_of!(FrameUniforms, camera_chunk)),
                    ("material_count", offset_of!(FrameUniforms, material_count)),
                    ("smooth_extent", offset_of!(FrameUniforms, smooth_extent)),
                    ("smooth_origin", offset_of!(FrameUniforms, smooth_origin)),
                    ("width", offset_of!(FrameUniforms, width)),
                    ("height", offset_of!(FrameUniforms, height)),
                    ("lighting", offset_of!(FrameUniforms, lighting)),
                    ("forward", offset_of!(FrameUniforms, forward)),
                    ("near", offset_of!(FrameUniforms, near)),
                    ("right", offset_of!(FrameUniforms, right)),
                    ("flags", offset_of!(FrameUniforms, flags)),
                    ("up", offset_of!(FrameUniforms, up)),
                    ("pad", offset_of!(FrameUniforms, pad)),
                ],
            );
            check(
                &module,
                "Lighting",
                size_of::<LightingUniforms>(),
                &[
                    ("sun_direction", offset_of!(LightingUniforms, sun_direction)),
                    (
                        "ambient_strength",
                        offset_of!(LightingUniforms, ambient_strength),
                    ),
                    ("sun_colour", offset_of!(LightingUniforms, sun_colour)),
                    (
                        "emissive_scale",
                        offset_of!(LightingUniforms, emissive_scale),
                    ),
                    ("sky_colour", offset_of!(LightingUniforms, sky_colour)),
                    (
                        "haze_inverse_distance",
                        offset_of!(LightingUniforms, haze_inverse_distance),
                    ),
                    ("ground_colour", offset_of!(LightingUniforms, ground_colour)),
                    ("ao_floor", offset_of!(LightingUniforms, ao_floor)),
                    ("exposure", offset_of!(LightingUniforms, exposure)),
                    ("sun_disc_cos", offset_of!(LightingUniforms, sun_disc_cos)),
                    ("zenith_colour", offset_of!(LightingUniforms, zenith_colour)),
                    (
                        "sun_disc_brightness",
                        offset_of!(LightingUniforms, sun_disc_brightness),
                    ),
                    (
                        "horizon_colour",
                        offset_of!(LightingUniforms, horizon_colour),
                    ),
                    ("sun_halo", offset_of!(LightingUniforms, sun_halo)),
                ],
            );
            check(
                &module,
                "GpuMaterial",
                8,
                &[("colour", 0), ("properties", 4)],
            );
        }
        let module = validate(GBUFFER.name, &GBUFFER.source()).unwrap();
        check(
            &module,
            "DrawRecord",
            size_of::<render_model::cull::DrawRecord>(),
            &[
                ("chunk_x", 0),
                ("chunk_y", 4),
                ("chunk_z", 8),
                ("level", 12),
            ],
        );
        check(
            &module,
            "SmoothDraw",
            size_of::<SmoothDraw>(),
            &[
                ("chunk_x", 0),
                ("chunk_y", 4),
                ("chunk_z", 8),
                ("vertex_offset", offset_of!(SmoothDraw, vertex_offset)),
                ("quad_offset", offset_of!(SmoothDraw, quad_offset)),
                ("quad_count", offset_of!(SmoothDraw, quad_count)),
                ("quad_form", offset_of!(SmoothDraw, quad_form)),
                ("level", offset_of!(SmoothDraw, level)),
            ],
        );
    }
}

mod quad_raster {
    use std::mem::offset_of;

    use render_model::quad_raster::*;

    use crate::shaders::{QUAD_RASTER, QUAD_RASTER_ARGS, struct_layout, validate_with};

    fn module(spec: crate::shaders::ShaderSpec) -> naga::Module {
        validate_with(spec.name, &spec.source(), spec.capabilities)
            .unwrap_or_else(|e| panic!("{e}"))
    }

    fn members(module: &naga::Module, name: &str) -> (Vec<(String, usize)>, usize) {
        struct_layout(module, name)
    }

    /// The value of the WGSL constant `name`.
    fn constant(module: &naga::Module, name: &str) -> naga::Literal {
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no constant {name}"));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(l) => l,
            ref e => panic!("{name} is not a literal: {e:?}"),
        }
    }

    #[test]
    fn structs_match_their_wgsl_twins() {
        let m = module(QUAD_RASTER);
        let (got, size) = members(&m, "RasterQuad");
        assert_eq!(size, size_of::<RasterQuad>());
        let want = [
            ("plane", offset_of!(RasterQuad, plane)),
            ("lo_w", offset_of!(RasterQuad, lo_w)),
            ("lo_h", offset_of!(RasterQuad, lo_h)),
            ("hi_w", offset_of!(RasterQuad, hi_w)),
            ("hi_h", offset_of!(RasterQuad, hi_h)),
            ("face_ao_block", offset_of!(RasterQuad, face_ao_block)),
            ("box_lo", offset_of!(RasterQuad, box_lo)),
            ("box_hi", offset_of!(RasterQuad, box_hi)),
        ];
        let got: Vec<(&str, usize)> = got.iter().map(|(n, o)| (n.as_str(), *o)).collect();
        assert_eq!(got, want);
        let (got, size) = members(&m, "PageArgs");
        assert_eq!(size, size_of::<PageArgs>());
        let offsets: Vec<usize> = got.iter().map(|m| m.1).collect();
        assert_eq!(offsets, [0, 4, 8, 12, 16, 20, 24, 28]);
        assert_eq!(offset_of!(PageArgs, first_command), 12);
        assert_eq!(offset_of!(PageArgs, commands), 16);
        assert_eq!(offset_of!(PageArgs, page), 20);
        let (got, size) = members(&m, "DrawRecord");
        assert_eq!(size, size_of::<render_model::cull::DrawRecord>());
        let got: Vec<(&str, usize)> = got.iter().map(|(n, o)| (n.as_str(), *o)).collect();
        assert_eq!(
            got,
            [
                ("chunk_x", 0),
                ("chunk_y", 4),
                ("chunk_z", 8),
                ("level", 12)
            ]
        );
        let a = module(QUAD_RASTER_ARGS);
        let (got, size) = members(&a, "ArgsParams");
        assert_eq!(size, size_of::<ArgsParams>());
        let got: Vec<(&str, usize)> = got.iter().map(|(n, o)| (n.as_str(), *o)).collect();
        assert_eq!(
            got,
            [
                ("page_count", offset_of!(ArgsParams, page_count)),
                (
                    "commands_per_page",
                    offset_of!(ArgsParams, commands_per_page)
                ),
                ("page_stride", offset_of!(ArgsParams, page_stride)),
                ("tile_capacity", offset_of!(ArgsParams, tile_capacity)),
            ]
        );
    }

    #[test]
    fn constants_match_their_wgsl_twins() {
        use naga::Literal::{F32, U32};
        let m = module(QUAD_RASTER);
        assert_eq!(constant(&m, "QR_WORKGROUP"), U32(WORKGROUP));
        assert_eq!(constant(&m, "QR_TILE"), U32(TILE));
        assert_eq!(constant(&m, "QR_LOCAL_MAX_PIXELS"), U32(LOCAL_MAX_PIXELS));
        assert_eq!(constant(&m, "QR_EPS_PX"), F32(EPS_PX));
        assert_eq!(constant(&m, "QR_EPS_MIN"), F32(EPS_MIN));
        assert_eq!(constant(&m, "QR_MAX_T"), F32(MAX_T));
        assert_eq!(constant(&m, "QR_NEAR_CLIP"), F32(NEAR_CLIP));
        assert_eq!(constant(&m, "QR_BOX_PAD"), F32(BOX_PAD));
        for (name, word) in [
            ("QR_TILE_COUNT", StateWord::TileCount),
            ("QR_BIG_COUNT", StateWord::BigCount),
            ("QR_STAT_QUADS", StateWord::Quads),
            ("QR_STAT_VISIBLE", StateWord::Visible),
            ("QR_STAT_LOCAL_PIXELS", StateWord::LocalPixels),
            ("QR_STAT_BIG", StateWord::Big),
            ("QR_STAT_OVERFLOW", StateWord::Overflow),
            ("QR_STAT_TILE_PIXELS", StateWord::TilePixels),
            ("QR_STAT_HITS", StateWord::Hits),
        ] {
            assert_eq!(constant(&m, name), U32(word as u32), "{name}");
            let stat = (word as u32) >= FIRST_STAT_WORD;
            assert_eq!(stat, name.starts_with("QR_STAT"), "{name}");
            assert!((word as u32) < STATE_WORDS);
        }
        let a = module(QUAD_RASTER_ARGS);
        assert_eq!(
            constant(&a, "QR_TILE_COUNT"),
            U32(StateWord::TileCount as u32)
        );
        assert_eq!(constant(&a, "MAX_GROUPS"), U32(MAX_GROUPS));
        assert_eq!(constant(&a, "QR_FIRST_STAT_WORD"), U32(FIRST_STAT_WORD));
        for (name, spec) in [("qr_quads", &m), ("qr_tiles", &m)] {
            let ep = spec.entry_points.iter().find(|e| e.name == name).unwrap();
            assert_eq!(ep.workgroup_size, [WORKGROUP, 1, 1], "{name}");
        }
    }
}

mod hiz {
    use render_model::hiz::level_sizes;

    #[test]
    fn pyramid_levels_are_the_wgpu_mip_chain() {
        // A wgpu texture of level 0's size has exactly these mips.
        for (w, h) in [(37, 23), (1920, 1080), (1, 7), (1000, 3), (8193, 2)] {
            let sizes = level_sizes(w, h).unwrap();
            let base = wgpu::Extent3d {
                width: sizes[0].0,
                height: sizes[0].1,
                depth_or_array_layers: 1,
            };
            assert_eq!(
                sizes.len() as u32,
                base.max_mips(wgpu::TextureDimension::D2)
            );
            for (m, &(lw, lh)) in sizes.iter().enumerate() {
                let mip = base.mip_level_size(m as u32, wgpu::TextureDimension::D2);
                assert_eq!((mip.width, mip.height), (lw, lh), "{w}x{h} level {m}");
            }
        }
    }
}

mod grass {
    use std::mem::offset_of;

    use render_model::grass::*;

    use crate::shaders::{GRASS, GRASS_CULL, struct_layout, validate};

    fn module(spec: crate::shaders::ShaderSpec) -> naga::Module {
        validate(spec.name, &spec.source()).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The value of the WGSL constant `name` (a literal, or a vector of literals).
    fn constant(module: &naga::Module, name: &str) -> Vec<naga::Literal> {
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no constant {name}"));
        let literal = |h: naga::Handle<naga::Expression>| match module.global_expressions[h] {
            naga::Expression::Literal(l) => l,
            ref e => panic!("{name} is not a literal: {e:?}"),
        };
        match &module.global_expressions[c.init] {
            naga::Expression::Compose { components, .. } => {
                components.iter().map(|&h| literal(h)).collect()
            }
            _ => vec![literal(c.init)],
        }
    }

    #[test]
    fn uniforms_match_their_wgsl_twins() {
        let cull = module(GRASS_CULL);
        let (members, size) = struct_layout(&cull, "GrassCullUniforms");
        assert_eq!(size, size_of::<GrassCullUniforms>());
        let expected = [
            ("planes", offset_of!(GrassCullUniforms, planes)),
            ("camera_chunk", offset_of!(GrassCullUniforms, camera_chunk)),
            ("slot_bound", offset_of!(GrassCullUniforms, slot_bound)),
            (
                "camera_offset",
                offset_of!(GrassCullUniforms, camera_offset),
            ),
            ("chunk_edge", offset_of!(GrassCullUniforms, chunk_edge)),
            ("lod", offset_of!(GrassCullUniforms, lod)),
            ("flags", offset_of!(GrassCullUniforms, flags)),
            ("focal_px", offset_of!(GrassCullUniforms, focal_px)),
            ("budget_px", offset_of!(GrassCullUniforms, budget_px)),
            ("pad", offset_of!(GrassCullUniforms, pad)),
        ]
        .map(|(n, o)| (n.to_string(), o));
        assert_eq!(members, expected);
        let draw = module(GRASS);
        let (members, size) = struct_layout(&draw, "GrassUniforms");
        assert_eq!(size, size_of::<GrassUniforms>());
        let expected = [
            ("wind_phase", offset_of!(GrassUniforms, wind_phase)),
            ("wind_strength", offset_of!(GrassUniforms, wind_strength)),
            ("focal_px", offset_of!(GrassUniforms, focal_px)),
            ("budget_px", offset_of!(GrassUniforms, budget_px)),
        ]
        .map(|(n, o)| (n.to_string(), o));
        assert_eq!(members, expected);
    }

    #[test]
    fn constants_match_their_wgsl_twins() {
        use naga::Literal::{F32, U32};
        let draw = module(GRASS);
        let cull = module(GRASS_CULL);
        let f = |m: &naga::Module, name| constant(m, name);
        assert_eq!(f(&draw, "BLADE_HEIGHT"), [F32(BLADE_HEIGHT)]);
        assert_eq!(f(&draw, "BLADE_WIDTH_RATIO"), [F32(BLADE_WIDTH_RATIO)]);
        assert_eq!(f(&draw, "WIND_SWAY"), [F32(WIND_SWAY)]);
        assert_eq!(f(&draw, "WIND_SPACE"), [F32(WIND_SPACE)]);
        assert_eq!(f(&draw, "WIND_SEED"), [F32(WIND_SEED)]);
        assert_eq!(f(&draw, "WIND_DIRECTION"), WIND_DIRECTION.map(F32));
        assert_eq!(f(&draw, "FADE_FULL"), [F32(FADE_FULL)]);
        assert_eq!(f(&draw, "FADE_DROP"), [F32(FADE_DROP)]);
        assert_eq!(f(&cull, "FADE_DROP"), [F32(FADE_DROP)]);
        assert_eq!(f(&draw, "VERTICES_PER_UNIT"), [U32(VERTICES_PER_UNIT)]);
        assert_eq!(f(&draw, "FLOWER_HEAD_RADIUS"), [F32(FLOWER_HEAD_RADIUS)]);
        assert_eq!(
            f(&draw, "FLOWER_STEM_HALF_WIDTH"),
            [F32(FLOWER_STEM_HALF_WIDTH)]
        );
        assert_eq!(f(&draw, "FLOWER_STEM"), FLOWER_STEM.map(F32));
        assert_eq!(f(&draw, "BLADE_BASE_SHADE"), [F32(BLADE_BASE_SHADE)]);
        assert_eq!(f(&cull, "MAX_BLADE_HEIGHT"), [F32(MAX_BLADE_HEIGHT)]);
        assert_eq!(f(&cull, "WIND_SWAY"), [F32(WIND_SWAY)]);
        assert_eq!(f(&cull, "FADE_FULL"), [F32(FADE_FULL)]);
        assert_eq!(f(&cull, "VERTICES_PER_UNIT"), [U32(VERTICES_PER_UNIT)]);
        assert_eq!(f(&cull, "GRASS_CULL_LOD"), [U32(GRASS_CULL_LOD)]);
        assert_eq!(
            f(&cull, "GRASS_CULL_OCCLUSION"),
            [U32(GRASS_CULL_OCCLUSION)]
        );
    }
}

mod props {
    use std::mem::offset_of;

    use render_model::props::*;

    use crate::render::props::PropMaterialUniform;
    use crate::shaders::{PROP_CULL, PROPS, ShaderSpec, struct_layout, validate_with};

    fn module(spec: ShaderSpec) -> naga::Module {
        validate_with(spec.name, &spec.source(), spec.capabilities)
            .unwrap_or_else(|e| panic!("{e}"))
    }

    fn want(list: &[(&str, usize)]) -> Vec<(String, usize)> {
        list.iter().map(|(n, o)| (n.to_string(), *o)).collect()
    }

    #[test]
    fn instance_record_matches_its_wgsl_twin() {
        for spec in [PROP_CULL, PROPS] {
            let (got, size) = struct_layout(&module(spec), "PropInstance");
            assert_eq!(size, size_of::<PropInstanceRecord>());
            let local = offset_of!(PropInstanceRecord, local);
            assert_eq!(
                got,
                want(&[
                    ("anchor_x", 0),
                    ("anchor_y", 4),
                    ("anchor_z", 8),
                    ("batch", offset_of!(PropInstanceRecord, batch)),
                    ("local", local),
                ])
            );
        }
    }

    #[test]
    fn batch_record_matches_its_wgsl_twin() {
        let (got, size) = struct_layout(&module(PROP_CULL), "PropBatch");
        assert_eq!(size, size_of::<PropBatchRecord>());
        let args = offset_of!(PropBatchRecord, args);
        let centre = offset_of!(PropBatchRecord, sphere_centre);
        assert_eq!(
            got,
            want(&[
                ("index_count", args),
                ("instance_count", args + 4),
                ("first_index", args + 8),
                ("base_vertex", args + 12),
                ("first_instance", args + 16),
                ("visible_count", offset_of!(PropBatchRecord, visible_count)),
                ("live_count", offset_of!(PropBatchRecord, live_count)),
                ("material", offset_of!(PropBatchRecord, material)),
                ("sphere_x", centre),
                ("sphere_y", centre + 4),
                ("sphere_z", centre + 8),
                ("sphere_radius", offset_of!(PropBatchRecord, sphere_radius)),
            ])
        );
        // The args are wgpu's DrawIndexedIndirect bytes.
        assert_eq!(size_of::<wgpu::util::DrawIndexedIndirectArgs>(), 20);
    }

    #[test]
    fn cull_uniforms_match_their_wgsl_twin() {
        for spec in [PROP_CULL, PROPS] {
            let (got, size) = struct_layout(&module(spec), "PropCullUniforms");
            assert_eq!(size, size_of::<PropCullUniforms>());
            assert_eq!(
                got,
                want(&[
                    ("view_proj", offset_of!(PropCullUniforms, view_proj)),
                    ("planes", offset_of!(PropCullUniforms, planes)),
                    ("eye_voxel", offset_of!(PropCullUniforms, eye_voxel)),
                    ("slot_count", offset_of!(PropCullUniforms, slot_count)),
                    ("eye_fraction", offset_of!(PropCullUniforms, eye_fraction)),
                    ("near", offset_of!(PropCullUniforms, near)),
                    ("screen", offset_of!(PropCullUniforms, screen)),
                    ("flags", offset_of!(PropCullUniforms, flags)),
                    ("batch_count", offset_of!(PropCullUniforms, batch_count)),
                ])
            );
        }
    }

    #[test]
    fn material_uniform_matches_its_wgsl_twin() {
        let (got, size) = struct_layout(&module(PROPS), "PropMaterial");
        assert_eq!(size, size_of::<PropMaterialUniform>());
        assert_eq!(
            got,
            want(&[
                ("base_colour", offset_of!(PropMaterialUniform, base_colour)),
                ("emissive", offset_of!(PropMaterialUniform, emissive)),
                ("cutoff", offset_of!(PropMaterialUniform, cutoff)),
                ("textured", offset_of!(PropMaterialUniform, textured)),
                (
                    "double_sided",
                    offset_of!(PropMaterialUniform, double_sided)
                ),
                (
                    "emissive_textured",
                    offset_of!(PropMaterialUniform, emissive_textured)
                ),
            ])
        );
    }

    #[test]
    fn constants_match_their_wgsl_twins() {
        let m = module(PROP_CULL);
        let value = |name: &str| {
            let (_, c) = m
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no constant {name}"));
            match m.global_expressions[c.init] {
                naga::Expression::Literal(naga::Literal::U32(v)) => v,
                ref e => panic!("{name} is not a u32 literal: {e:?}"),
            }
        };
        assert_eq!(value("PROP_NO_BATCH"), NO_BATCH);
        assert_eq!(value("PROP_CULL_FRUSTUM"), PROP_CULL_FRUSTUM);
        assert_eq!(value("PROP_CULL_OCCLUSION"), PROP_CULL_OCCLUSION);
    }

    #[test]
    fn emission_constants_match_their_wgsl_twins() {
        use render_model::props::{EMISSION_BIAS, EMISSION_FLAG, EMISSION_MAX, EMISSION_MIN};
        let m = module(PROPS);
        let literal = |name: &str| {
            let (_, c) = m
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no constant {name}"));
            match m.global_expressions[c.init] {
                naga::Expression::Literal(l) => l,
                ref e => panic!("{name} is not a literal: {e:?}"),
            }
        };
        assert_eq!(literal("EMISSION_BIAS"), naga::Literal::I32(EMISSION_BIAS));
        assert_eq!(literal("EMISSION_MAX"), naga::Literal::F32(EMISSION_MAX));
        assert_eq!(literal("EMISSION_MIN"), naga::Literal::F32(EMISSION_MIN));
        assert_eq!(literal("EMISSION_FLAG"), naga::Literal::U32(EMISSION_FLAG));
    }
}

mod shadow {
    use std::mem::offset_of;

    use render_model::frame::{FRAME_SHADOWS, FRAME_SPLAT};
    use render_model::lighting::shadow::{BRICK, GRID_CELLS, SKY_DIRECTIONS, Visibility};
    use render_model::lighting::{
        SHADOW_FILL_LOD, SHADOW_SKY, SHADOW_SUN, ShadowFillUniforms, ShadowTraceUniforms,
    };

    use crate::shaders::{LIGHTING, SHADOW_FILL, SHADOW_TRACE, struct_layout, validate};

    fn layout(spec: crate::shaders::ShaderSpec, name: &str) -> (Vec<(String, usize)>, usize) {
        let module = validate(spec.name, &spec.source()).unwrap_or_else(|e| panic!("{e}"));
        struct_layout(&module, name)
    }

    fn names(members: &[(String, usize)]) -> Vec<(&str, usize)> {
        members.iter().map(|(n, o)| (n.as_str(), *o)).collect()
    }

    #[test]
    fn uniforms_match_their_wgsl_twins() {
        let (members, size) = layout(SHADOW_TRACE, "ShadowTraceUniforms");
        assert_eq!(size, size_of::<ShadowTraceUniforms>());
        assert_eq!(
            names(&members),
            [
                ("fraction", offset_of!(ShadowTraceUniforms, fraction)),
                ("flags", offset_of!(ShadowTraceUniforms, flags)),
                ("max_steps", offset_of!(ShadowTraceUniforms, max_steps)),
                (
                    "max_distance",
                    offset_of!(ShadowTraceUniforms, max_distance)
                ),
                ("normal_bias", offset_of!(ShadowTraceUniforms, normal_bias)),
                (
                    "sky_distance",
                    offset_of!(ShadowTraceUniforms, sky_distance)
                ),
            ]
        );
        let (members, size) = layout(SHADOW_FILL, "ShadowFillUniforms");
        assert_eq!(size, size_of::<ShadowFillUniforms>());
        assert_eq!(
            names(&members),
            [
                ("lod", offset_of!(ShadowFillUniforms, lod)),
                ("camera_chunk", offset_of!(ShadowFillUniforms, camera_chunk)),
                ("slot_bound", offset_of!(ShadowFillUniforms, slot_bound)),
                ("camera_block", offset_of!(ShadowFillUniforms, camera_block)),
                ("chunk_edge", offset_of!(ShadowFillUniforms, chunk_edge)),
                ("flags", offset_of!(ShadowFillUniforms, flags)),
                ("page", offset_of!(ShadowFillUniforms, page)),
                (
                    "page_capacity",
                    offset_of!(ShadowFillUniforms, page_capacity)
                ),
                (
                    "bound_capacity",
                    offset_of!(ShadowFillUniforms, bound_capacity)
                ),
            ]
        );
    }

    #[test]
    fn constants_match_their_wgsl_twins() {
        let fill = SHADOW_FILL.source();
        let trace = SHADOW_TRACE.source();
        let lighting = LIGHTING.source();
        let grid = format!("const GRID_CELLS: i32 = {GRID_CELLS};");
        assert!(fill.contains(&grid) && trace.contains(&grid));
        assert!(trace.contains(&format!("const BRICK: i32 = {BRICK};")));
        assert!(fill.contains(&format!("const SHADOW_FILL_LOD: u32 = {SHADOW_FILL_LOD}u;")));
        assert!(trace.contains(&format!("const SHADOW_SUN: u32 = {SHADOW_SUN}u;")));
        assert!(trace.contains(&format!("const SHADOW_SKY: u32 = {SHADOW_SKY}u;")));
        let sky = SKY_DIRECTIONS.len();
        assert!(trace.contains(&format!("const SKY_COUNT: u32 = {sky}u;")));
        for source in [&trace, &lighting] {
            assert!(source.contains(&format!("const FRAME_SPLAT: u32 = {FRAME_SPLAT}u;")));
            assert!(source.contains(&format!("const FRAME_SHADOWS: u32 = {FRAME_SHADOWS}u;")));
        }
        // The sky directions: straight up and four at 45 degrees (the trace writes them with
        // h = 1 / sqrt(2) rounded to f32).
        let h = core::f32::consts::FRAC_1_SQRT_2;
        assert_eq!(format!("{h}"), "0.70710677");
        assert!(trace.contains("let h = 0.70710677;"));
        for d in SKY_DIRECTIONS {
            let term = |c: f32| match c {
                0.0 => "0.0".to_owned(),
                1.0 => "1.0".to_owned(),
                c if c == h => "h".to_owned(),
                c if c == -h => "-h".to_owned(),
                c => panic!("unexpected sky component {c}"),
            };
            let v = format!("vec3<f32>({}, {}, {})", term(d[0]), term(d[1]), term(d[2]));
            assert!(trace.contains(&v), "{v} missing from the trace");
        }
        // The lighting pass unpacks the words as Visibility does.
        assert!(lighting.contains("f32(min((w >> 1u) & 7u, 5u)) / 5.0"));
        assert_eq!(Visibility::OPEN.pack(), 1 | (5 << 1));
        assert!(trace.contains("shadow_out[at] = 1u | (SKY_COUNT << 1u);"));
    }
}

mod shells {
    //! The shell pass's twins: its cull uniforms share `GrassCullUniforms`' layout and flags,
    //! and its vertex count per run is `ShellRun::VERTICES`.

    use std::mem::offset_of;

    use render_model::grass::{
        GRASS_CULL_LOD, GRASS_CULL_OCCLUSION, GrassCullUniforms, SHELL_CULL_FAR,
    };
    use voxel_core::formats::ShellRun;

    use crate::shaders::{SHELLS, SHELLS_CULL, struct_layout, validate};

    fn module(spec: crate::shaders::ShaderSpec) -> naga::Module {
        validate(spec.name, &spec.source()).unwrap_or_else(|e| panic!("{e}"))
    }

    fn has_constant(module: &naga::Module, name: &str, value: u32) -> bool {
        module.constants.iter().any(|(_, c)| {
            c.name.as_deref() == Some(name)
                && matches!(
                    module.global_expressions[c.init],
                    naga::Expression::Literal(naga::Literal::U32(v)) if v == value
                )
        })
    }

    #[test]
    fn cull_uniforms_and_constants_match_their_rust_twins() {
        let cull = module(SHELLS_CULL);
        let (members, size) = struct_layout(&cull, "ShellCullUniforms");
        assert_eq!(size, size_of::<GrassCullUniforms>());
        let expected = [
            ("planes", offset_of!(GrassCullUniforms, planes)),
            ("camera_chunk", offset_of!(GrassCullUniforms, camera_chunk)),
            ("slot_bound", offset_of!(GrassCullUniforms, slot_bound)),
            (
                "camera_offset",
                offset_of!(GrassCullUniforms, camera_offset),
            ),
            ("chunk_edge", offset_of!(GrassCullUniforms, chunk_edge)),
            ("lod", offset_of!(GrassCullUniforms, lod)),
            ("flags", offset_of!(GrassCullUniforms, flags)),
            ("focal_px", offset_of!(GrassCullUniforms, focal_px)),
            ("far_cell_px", offset_of!(GrassCullUniforms, budget_px)),
            ("pad", offset_of!(GrassCullUniforms, pad)),
        ]
        .map(|(n, o)| (n.to_string(), o));
        assert_eq!(members, expected);
        assert!(has_constant(&cull, "SHELL_CULL_LOD", GRASS_CULL_LOD));
        assert!(has_constant(&cull, "SHELL_CULL_FAR", SHELL_CULL_FAR));
        assert!(has_constant(
            &cull,
            "SHELL_CULL_OCCLUSION",
            GRASS_CULL_OCCLUSION
        ));
        for m in [cull, module(SHELLS)] {
            assert!(has_constant(&m, "VERTICES_PER_RUN", ShellRun::VERTICES));
        }
    }
}
