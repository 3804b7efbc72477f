//! STL reading (ASCII and binary), welding, cleanup, errors, and writing.
//!
//! Fixtures in `tests/data/`: a unit cube (12 facets, area 6 m², volume 1 m³) and a right
//! triangular prism "wedge" (legs 2 m along x and 1 m along z, 3 m along y: volume 3 m³, area
//! 11 + 3√5 m²), each as ASCII and binary; `cube_binary.stl`'s header starts with "solid", as
//! some exporters write, to exercise format detection by size (84 + 50 n bytes).

use std::path::{Path, PathBuf};

use approx::assert_relative_eq;
use hsv_core::mesh::{PanelMesh, PanelSpec, RegionKind, Strip, Surface};
use hsv_core::stl::{
    StlError, parse_stl, parse_stl_with_report, read_stl, read_stl_with_report, stl_ascii_string,
    stl_binary_bytes, write_stl_ascii, write_stl_binary,
};
use nalgebra::Point3;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("hsv-stl-test-{}-{name}", std::process::id()))
}

fn err_string(r: Result<PanelMesh, StlError>) -> String {
    match r {
        Ok(m) => panic!("expected an error, got a mesh of {} panels", m.panels.len()),
        Err(e) => e.to_string(),
    }
}

fn cube_ascii() -> String {
    std::fs::read_to_string(data("cube_ascii.stl")).expect("fixture")
}

#[test]
fn reads_the_cube_fixtures_ascii_and_binary() {
    for (file, binary) in [("cube_ascii.stl", false), ("cube_binary.stl", true)] {
        let (mesh, report) = read_stl_with_report(&data(file)).expect(file);
        assert_eq!(report.binary, binary, "{file}");
        assert_eq!(report.facets_read, 12);
        assert_eq!(report.degenerate_dropped, 0);
        assert_eq!(report.reoriented, 0);
        assert_eq!(mesh.vertices.len(), 8, "{file}: duplicate vertices welded");
        assert_eq!(mesh.panels.len(), 12);
        assert!(
            mesh.is_closed() && mesh.is_consistently_oriented(),
            "{file}"
        );
        assert!(!mesh.is_structured());
        assert_relative_eq!(mesh.total_area_m2(), 6.0, max_relative = 1e-12);
        assert_relative_eq!(mesh.enclosed_volume_m3(), 1.0, max_relative = 1e-12);
        assert_eq!(mesh.surfaces.len(), 1);
        assert_eq!(mesh.surfaces[0].name, file.trim_end_matches(".stl"));
        assert_eq!(mesh.surfaces[0].region, RegionKind::Other);
        assert_eq!(mesh.panels_in_region(RegionKind::Other).count(), 12);
    }
}

#[test]
fn reads_the_wedge_fixtures_ascii_and_binary() {
    let area = 11.0 + 3.0 * 5f64.sqrt();
    for file in ["wedge_ascii.stl", "wedge_binary.stl"] {
        let mesh = read_stl(&data(file)).expect(file);
        assert_eq!(mesh.vertices.len(), 6);
        assert_eq!(mesh.panels.len(), 8);
        assert!(mesh.is_closed() && mesh.is_consistently_oriented());
        assert_relative_eq!(mesh.total_area_m2(), area, max_relative = 1e-7);
        assert_relative_eq!(mesh.enclosed_volume_m3(), 3.0, max_relative = 1e-7);
        let (lo, hi) = mesh.bounding_box();
        assert_eq!(lo, Point3::new(0.0, 0.0, 0.0));
        assert_eq!(hi, Point3::new(2.0, 3.0, 1.0));
    }
}

#[test]
fn facets_wound_against_their_normal_are_turned() {
    // Swap two vertices of the first facet; its stored normal still points out.
    let text = cube_ascii();
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let first_vertex = lines
        .iter()
        .position(|l| l.trim_start().starts_with("vertex"))
        .expect("a vertex");
    lines.swap(first_vertex + 1, first_vertex + 2);
    let (mesh, report) =
        parse_stl_with_report(lines.join("\n").as_bytes(), "flipped.stl").expect("parses");
    assert_eq!(report.reoriented, 1);
    assert!(mesh.is_consistently_oriented());
    assert_relative_eq!(mesh.enclosed_volume_m3(), 1.0, max_relative = 1e-12);
}

#[test]
fn zero_area_facets_are_dropped_and_counted() {
    let extra = "  facet normal 0 0 0\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0.5 0 0\n    endloop\n  endfacet\n";
    let text = cube_ascii().replace("endsolid", &format!("{extra}endsolid"));
    let (mesh, report) = parse_stl_with_report(text.as_bytes(), "degenerate.stl").expect("parses");
    assert_eq!(report.facets_read, 13);
    assert_eq!(report.degenerate_dropped, 1);
    assert_eq!(mesh.panels.len(), 12);
    // The collinear facet's midpoint vertex is not left behind.
    assert_eq!(mesh.vertices.len(), 8);
    assert!(mesh.is_closed());
}

#[test]
fn nearly_coincident_vertices_are_welded() {
    // Perturb one vertex occurrence by 1e-9 m (1e-9 of the cube's size): still one vertex.
    let text = cube_ascii().replacen(
        "vertex 1.000000e+00 1.000000e+00 0.000000e+00",
        "vertex 1.000000001 1 0",
        1,
    );
    assert_ne!(text, cube_ascii(), "fixture format changed");
    let mesh = parse_stl(text.as_bytes(), "welded.stl").expect("parses");
    assert_eq!(mesh.vertices.len(), 8);
    assert!(mesh.is_closed());
}

#[test]
fn errors_name_the_file_and_the_problem() {
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (Vec::new(), "file is empty"),
        (b"  \n\t ".to_vec(), "file is empty"),
        (vec![1u8; 10], "too short for a binary STL"),
        (b"solid x\nendsolid x\n".to_vec(), "no facets"),
        (
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0\n".to_vec(),
            "line 4: `vertex` needs 3 numbers, found 2",
        ),
        (
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 a\n".to_vec(),
            "line 4: `a` in `vertex` is not a number",
        ),
        (
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n  endloop\n".to_vec(),
            "line 5: facet has 1 vertices, needs 3",
        ),
        (
            b"solid x\n facet normal 0 0 1\n  inner loop\n".to_vec(),
            "line 3: expected `outer loop`",
        ),
        (
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n"
                .to_vec(),
            "",
        ),
        (
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n"
                .to_vec(),
            "missing `endfacet`/`endsolid`",
        ),
        (
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex nan 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid\n"
                .to_vec(),
            "facet 0 has a non-finite coordinate",
        ),
        (
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 2 0 0\n  endloop\n endfacet\nendsolid\n"
                .to_vec(),
            "all 1 facets have zero area",
        ),
    ];
    for (bytes, expected) in cases {
        let result = parse_stl(&bytes, "part.stl");
        if expected.is_empty() {
            // A complete facet without `endsolid` is accepted.
            assert!(result.is_ok());
            continue;
        }
        let err = err_string(result);
        assert!(err.starts_with("part.stl: "), "{err}");
        assert!(err.contains(expected), "expected `{expected}` in `{err}`");
        assert!(!err.contains('\n'), "one line: {err}");
    }
}

#[test]
fn truncated_binary_is_reported_even_with_a_solid_header() {
    let bytes = std::fs::read(data("cube_binary.stl")).expect("fixture");
    assert!(bytes.starts_with(b"solid"));
    let err = err_string(parse_stl(&bytes[..bytes.len() - 7], "cut.stl"));
    assert!(
        err.starts_with("cut.stl: binary STL declares 12 facets")
            && err.contains("684 bytes")
            && err.contains("677 bytes"),
        "{err}"
    );
    // A binary file with zero facets.
    let mut empty = vec![b' '; 80];
    empty.extend_from_slice(&0u32.to_le_bytes());
    assert!(err_string(parse_stl(&empty, "none.stl")).contains("no facets"));
    // NaN in a binary facet.
    let mut nan = bytes.clone();
    nan[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    assert!(err_string(parse_stl(&nan, "nan.stl")).contains("facet 0 has a non-finite"));
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let path = data("no-such-file.stl");
    let err = err_string(read_stl(&path));
    assert!(
        err.contains("no-such-file.stl") && err.contains("cannot read"),
        "{err}"
    );
}

fn quad_cube() -> PanelMesh {
    let v = |x: f64, y: f64, z: f64| Point3::new(x, y, z);
    PanelMesh::new(
        vec![
            v(0., 0., 0.),
            v(1., 0., 0.),
            v(1., 1., 0.),
            v(0., 1., 0.),
            v(0., 0., 1.),
            v(1., 0., 1.),
            v(1., 1., 1.),
            v(0., 1., 1.),
        ],
        &[
            PanelSpec::quad(0, 3, 2, 1, 0),
            PanelSpec::quad(4, 5, 6, 7, 0),
            PanelSpec::quad(0, 1, 5, 4, 0),
            PanelSpec::quad(3, 7, 6, 2, 0),
            PanelSpec::quad(0, 4, 7, 3, 0),
            PanelSpec::quad(1, 2, 6, 5, 0),
        ],
        vec![Strip { panels: vec![0, 1] }],
        vec![Surface::new("box", RegionKind::MainBody)],
    )
    .expect("valid cube")
}

#[test]
fn written_files_read_back() {
    let cube = quad_cube();
    let bin = temp_path("cube-out.stl");
    write_stl_binary(&cube, &bin).expect("write binary");
    let bytes = std::fs::read(&bin).expect("read back");
    assert_eq!(bytes.len(), 84 + 50 * 12);
    let back = read_stl(&bin).expect("parse binary");
    assert_eq!(back.panels.len(), 12);
    assert!(back.is_closed() && back.is_consistently_oriented());
    assert_relative_eq!(back.enclosed_volume_m3(), 1.0, max_relative = 1e-12);
    let ascii = temp_path("cube-out-ascii.stl");
    write_stl_ascii(&cube, &ascii).expect("write ascii");
    let back = read_stl(&ascii).expect("parse ascii");
    assert_relative_eq!(back.total_area_m2(), 6.0, max_relative = 1e-12);
    let _ = std::fs::remove_file(bin);
    let _ = std::fs::remove_file(ascii);
    // In-memory forms agree.
    let a = parse_stl(stl_ascii_string(&cube, "c").as_bytes(), "a.stl").expect("ascii");
    let b = parse_stl(&stl_binary_bytes(&cube, "solid c"), "b.stl").expect("binary");
    assert_eq!(a.vertices.len(), b.vertices.len());
    assert_relative_eq!(
        a.enclosed_volume_m3(),
        b.enclosed_volume_m3(),
        max_relative = 1e-12
    );
}

#[test]
fn the_sample_vehicle_body_survives_an_stl_round_trip() {
    let vehicle = hsv_core::config::LoadedConfig::sample()
        .expect("sample")
        .vehicle()
        .expect("sample vehicle");
    let body = &vehicle.body;
    let bytes = stl_binary_bytes(body, "sample body");
    let (back, report) = parse_stl_with_report(&bytes, "body.stl").expect("parses");
    assert_eq!(report.degenerate_dropped, 0);
    assert_eq!(report.reoriented, 0);
    assert_eq!(back.vertices.len(), body.vertices.len());
    assert!(back.is_closed() && back.is_consistently_oriented());
    // f32 coordinates: agreement to single precision.
    assert_relative_eq!(
        back.total_area_m2(),
        body.total_area_m2(),
        max_relative = 1e-5
    );
    assert_relative_eq!(
        back.enclosed_volume_m3(),
        body.enclosed_volume_m3(),
        max_relative = 1e-5
    );
}

/// The cube fixture's facets as text with facet `k` turned by `edit`.
fn cube_with(edit: impl Fn(usize, &str) -> Option<String>) -> String {
    let text = cube_ascii();
    let mut out = String::new();
    for (k, block) in text.split("  facet").enumerate() {
        if k == 0 {
            out += block;
            continue;
        }
        if let Some(new) = edit(k - 1, block) {
            out += "  facet";
            out += &new;
        }
    }
    out
}

/// A facet block with its vertex order reversed and its normal negated (an inward facet that
/// agrees with its stored normal, so the reader keeps it).
fn inside_out(block: &str) -> String {
    let lines: Vec<&str> = block.lines().collect();
    let normal: Vec<f64> = lines[0]
        .split_whitespace()
        .skip(1)
        .map(|t| t.parse::<f64>().expect("normal"))
        .collect();
    let vertices: Vec<&str> = lines
        .iter()
        .copied()
        .filter(|l| l.trim_start().starts_with("vertex"))
        .collect();
    format!(
        " normal {} {} {}\n    outer loop\n{}\n{}\n{}\n    endloop\n  endfacet\n",
        -normal[0], -normal[1], -normal[2], vertices[0], vertices[2], vertices[1]
    )
}

#[test]
fn closure_finds_open_misoriented_and_inward_meshes_and_reversal_turns_them_out() {
    let closed = parse_stl(cube_ascii().as_bytes(), "cube.stl").expect("cube");
    let c = closed.closure();
    assert!(c.is_closed_outward() && c.problems().is_empty(), "{c:?}");
    assert_relative_eq!(c.enclosed_volume_m3, 1.0, max_relative = 1e-12);

    // One facet missing: its three edges are open.
    let open = parse_stl(
        cube_with(|k, b| (k != 0).then(|| b.to_owned())).as_bytes(),
        "o.stl",
    )
    .expect("open cube");
    let c = open.closure();
    assert_eq!((c.boundary_edges, c.misoriented_edges), (3, 0));
    assert!(!c.is_closed() && c.problems()[0].contains("3 open edges"));

    // One facet inside out: its three edges are traversed twice the same way.
    let mixed = cube_with(|k, b| Some(if k == 0 { inside_out(b) } else { b.to_owned() }));
    let c = parse_stl(mixed.as_bytes(), "m.stl")
        .expect("mixed")
        .closure();
    assert_eq!((c.boundary_edges, c.misoriented_edges), (0, 3));
    assert!(c.is_closed() && !c.is_closed_outward() && !c.is_closed_inward());

    // Every facet inside out: closed, consistent, negative volume; reversing restores it.
    let inward = cube_with(|_, b| Some(inside_out(b)));
    let mut mesh = parse_stl(inward.as_bytes(), "i.stl").expect("inward");
    let c = mesh.closure();
    assert!(c.is_closed_inward(), "{c:?}");
    assert_relative_eq!(c.enclosed_volume_m3, -1.0, max_relative = 1e-12);
    mesh.reverse_orientation();
    assert!(mesh.closure().is_closed_outward());
    assert_relative_eq!(mesh.enclosed_volume_m3(), 1.0, max_relative = 1e-12);
    for (turned, original) in mesh.panels.iter().zip(&closed.panels) {
        assert_relative_eq!(turned.area_m2, original.area_m2, max_relative = 1e-12);
    }
    // Outward normals: the bottom face (z = 0) points to -z.
    let bottom = mesh
        .panels
        .iter()
        .find(|p| p.centroid.z < 1e-9)
        .expect("bottom");
    assert_relative_eq!(bottom.normal.z, -1.0, epsilon = 1e-12);
}

#[test]
fn welding_a_large_mesh_merges_exact_and_near_copies_alike() {
    // A 60 x 60 grid of points, each given four times: itself, a copy 4.7e-7 m away (inside
    // the 1e-6 m tolerance), a copy 1e-3 m away (outside it) and an exact copy.
    let mut points = Vec::new();
    for i in 0..60 {
        for j in 0..60 {
            let p = Point3::new(f64::from(i) * 0.01, f64::from(j) * 0.01, 0.0);
            points.push(p);
            points.push(p + nalgebra::Vector3::new(3e-7, -3e-7, 2e-7));
            points.push(p + nalgebra::Vector3::new(0.0, 0.0, 1e-3));
            points.push(p);
        }
    }
    let (unique, map) = hsv_core::mesh::weld_vertices(&points, 1e-6);
    assert_eq!(unique.len(), 2 * 3600);
    for k in 0..3600 {
        let [a, b, c, d] = [map[4 * k], map[4 * k + 1], map[4 * k + 2], map[4 * k + 3]];
        assert_eq!((a, a), (b, d), "point {k}");
        assert_ne!(a, c);
        // First come, first kept.
        assert_eq!(unique[a], points[4 * k]);
    }
}
