//! Cost of reading an STL file into a welded panel mesh, per facet: a closed torus of 200 000
//! triangles as binary STL (the size of a detailed vehicle export) and 20 000 as ASCII.
//!
//! `cargo bench -p hsv-benches --bench stl`. The bytes are made in memory by the writer, so the
//! bench measures parsing, welding, cleanup and mesh construction, not the disk.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use hsv_core::mesh::PanelMesh;
use hsv_core::stl::{parse_stl, stl_ascii_string, stl_binary_bytes};

/// A closed torus (radii 3 m and 1 m) of 2 × `n` × `n` outward-wound triangles, written as
/// ASCII STL and read back (the writer needs a mesh).
fn torus(n: usize) -> PanelMesh {
    use std::fmt::Write as _;
    let (big, small) = (3.0, 1.0);
    let tau = std::f64::consts::TAU;
    let point = |i: usize, j: usize| {
        let u = tau * (i % n) as f64 / n as f64;
        let v = tau * (j % n) as f64 / n as f64;
        let r = big + small * v.cos();
        [r * u.cos(), r * u.sin(), small * v.sin()]
    };
    let mut text = String::from("solid torus\n");
    let mut facet = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        // A zero normal: the reader keeps the winding.
        let _ = writeln!(text, "facet normal 0 0 0\nouter loop");
        for p in [a, b, c] {
            let _ = writeln!(text, "vertex {:e} {:e} {:e}", p[0], p[1], p[2]);
        }
        let _ = writeln!(text, "endloop\nendfacet");
    };
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            facet(a, b, c);
            facet(a, c, d);
        }
    }
    text.push_str("endsolid torus\n");
    parse_stl(text.as_bytes(), "torus.stl").expect("torus mesh")
}

fn read_stl(c: &mut Criterion) {
    let mut group = c.benchmark_group("stl/read-and-weld");
    group.sample_size(10);
    let binary = stl_binary_bytes(&torus(317), "torus");
    let facets = (binary.len() - 84) / 50;
    group.throughput(Throughput::Elements(facets as u64));
    group.bench_function(format!("binary-{facets}-facets"), |b| {
        b.iter(|| black_box(parse_stl(black_box(&binary), "torus.stl").expect("parses")))
    });
    let small = torus(100);
    let ascii = stl_ascii_string(&small, "torus");
    group.throughput(Throughput::Elements(small.panels.len() as u64));
    group.bench_function(format!("ascii-{}-facets", small.panels.len()), |b| {
        b.iter(|| black_box(parse_stl(black_box(ascii.as_bytes()), "torus.stl").expect("parses")))
    });
    group.finish();
}

criterion_group!(benches, read_stl);
criterion_main!(benches);
