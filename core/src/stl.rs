//! STL input and output: ASCII and binary STL files to and from unstructured panel meshes.
//!
//! Reading detects the format by size (a binary file is exactly 84 + 50 n bytes for its declared
//! n facets, even when its header starts with "solid"), welds duplicate vertices (tolerance
//! relative to the bounding box), drops zero-area facets and turns facets whose winding disagrees
//! with their stored normal. Coordinates are taken as metres in body axes (x forward, y right,
//! z down). The mesh has one surface named after the file, region [`RegionKind::Other`].
//! Reference: the STL format as specified by 3D Systems, *StereoLithography Interface
//! Specification* (1989).

use std::path::Path;

use nalgebra::{Point3, Vector3};

use crate::mesh::{MeshError, PanelMesh, RegionKind, Surface, bounding_box_of, weld_vertices};

/// Vertices closer than this fraction of the bounding-box diagonal are one vertex.
pub const WELD_TOLERANCE_RELATIVE: f64 = 1e-6;

/// Why an STL file could not be read or written. Every message starts with the file.
#[derive(Debug, thiserror::Error)]
pub enum StlError {
    #[error("{origin}: cannot {action}: {source}")]
    Io {
        origin: String,
        action: &'static str,
        source: std::io::Error,
    },
    #[error("{origin}: file is empty")]
    Empty { origin: String },
    #[error(
        "{origin}: not an ASCII STL (no leading `solid`) and too short for a binary STL ({bytes} bytes, a binary STL has at least 84)"
    )]
    TooShort { origin: String, bytes: usize },
    #[error(
        "{origin}: binary STL declares {facets} facets, which needs 84 + 50 x {facets} = {expected} bytes, but the file has {actual} bytes (truncated or not an STL)"
    )]
    BinarySize {
        origin: String,
        facets: u64,
        expected: u64,
        actual: usize,
    },
    #[error("{origin}: line {line}: {message}")]
    Malformed {
        origin: String,
        line: usize,
        message: String,
    },
    #[error("{origin}: no facets")]
    NoFacets { origin: String },
    #[error("{origin}: all {facets} facets have zero area")]
    AllDegenerate { origin: String, facets: usize },
    #[error("{origin}: facet {facet} has a non-finite coordinate (NaN or infinity)")]
    NonFinite { origin: String, facet: usize },
    #[error("{origin}: {source}")]
    Mesh { origin: String, source: MeshError },
}

/// What reading an STL did to the facets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StlReport {
    /// Facets in the file.
    pub facets_read: usize,
    /// Zero-area facets dropped (before or after welding).
    pub degenerate_dropped: usize,
    /// Facets whose vertex order was reversed to agree with their stored normal.
    pub reoriented: usize,
    /// Vertices in the mesh after welding.
    pub vertices: usize,
    /// True for binary files.
    pub binary: bool,
}

/// The facets as stored: facet i has normal `normals[i]` and vertices `points[3 i..3 i + 3]`.
#[derive(Default)]
struct Facets {
    normals: Vec<Vector3<f64>>,
    points: Vec<Point3<f64>>,
}

impl Facets {
    fn with_capacity(n: usize) -> Self {
        Self {
            normals: Vec::with_capacity(n),
            points: Vec::with_capacity(3 * n),
        }
    }

    fn len(&self) -> usize {
        self.normals.len()
    }

    fn is_empty(&self) -> bool {
        self.normals.is_empty()
    }

    fn push(&mut self, normal: Vector3<f64>, vertices: [Point3<f64>; 3]) {
        self.normals.push(normal);
        self.points.extend_from_slice(&vertices);
    }
}

/// Reads an ASCII or binary STL file into an unstructured mesh.
pub fn read_stl(path: &Path) -> Result<PanelMesh, StlError> {
    read_stl_with_report(path).map(|(mesh, _)| mesh)
}

/// [`read_stl`], also returning what was done to the facets.
pub fn read_stl_with_report(path: &Path) -> Result<(PanelMesh, StlReport), StlError> {
    let origin = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| StlError::Io {
        origin: origin.clone(),
        action: "read",
        source,
    })?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| origin.clone());
    parse_named(&bytes, &origin, &name)
}

/// Parses STL bytes; `origin` names the source in errors and (its file stem) the surface.
pub fn parse_stl(bytes: &[u8], origin: &str) -> Result<PanelMesh, StlError> {
    parse_stl_with_report(bytes, origin).map(|(mesh, _)| mesh)
}

/// [`parse_stl`], also returning what was done to the facets.
pub fn parse_stl_with_report(
    bytes: &[u8],
    origin: &str,
) -> Result<(PanelMesh, StlReport), StlError> {
    let name = Path::new(origin)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| origin.to_owned());
    parse_named(bytes, origin, &name)
}

fn parse_named(bytes: &[u8], origin: &str, name: &str) -> Result<(PanelMesh, StlReport), StlError> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(StlError::Empty {
            origin: origin.to_owned(),
        });
    }
    let (facets, binary) = if is_exact_binary(bytes) {
        (parse_binary(bytes, origin)?, true)
    } else if looks_ascii(bytes) {
        (parse_ascii(bytes, origin)?, false)
    } else {
        // Neither: report against the binary layout, which is what a non-text file claims.
        (parse_binary(bytes, origin)?, true)
    };
    let (mesh, mut report) = build_mesh(&facets, origin, name)?;
    report.binary = binary;
    Ok((mesh, report))
}

/// True when the size is exactly 84 + 50 n for the n facets declared at bytes 80..84.
fn is_exact_binary(bytes: &[u8]) -> bool {
    declared_facets(bytes).is_some_and(|n| 84 + 50 * n == bytes.len() as u64)
}

fn declared_facets(bytes: &[u8]) -> Option<u64> {
    let count: [u8; 4] = bytes.get(80..84)?.try_into().ok()?;
    Some(u64::from(u32::from_le_bytes(count)))
}

/// Starts with "solid" (after optional whitespace) and is NUL-free UTF-8 text.
fn looks_ascii(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let head = &bytes[start..];
    head.len() >= 5
        && head[..5].eq_ignore_ascii_case(b"solid")
        && !bytes.contains(&0)
        && std::str::from_utf8(bytes).is_ok()
}

fn parse_binary(bytes: &[u8], origin: &str) -> Result<Facets, StlError> {
    let Some(n) = declared_facets(bytes) else {
        return Err(StlError::TooShort {
            origin: origin.to_owned(),
            bytes: bytes.len(),
        });
    };
    let expected = 84 + 50 * n;
    if expected != bytes.len() as u64 {
        return Err(StlError::BinarySize {
            origin: origin.to_owned(),
            facets: n,
            expected,
            actual: bytes.len(),
        });
    }
    let xyz = |record: &[u8]| {
        let f = |k: usize| {
            let mut b = [0u8; 4];
            b.copy_from_slice(&record[4 * k..4 * k + 4]);
            f64::from(f32::from_le_bytes(b))
        };
        Vector3::new(f(0), f(1), f(2))
    };
    // The size check above guarantees every record is inside `bytes`.
    let mut facets = Facets::with_capacity(bytes[84..].len() / 50);
    for record in bytes[84..].chunks_exact(50) {
        facets.push(
            xyz(&record[0..12]),
            [
                Point3::from(xyz(&record[12..24])),
                Point3::from(xyz(&record[24..36])),
                Point3::from(xyz(&record[36..48])),
            ],
        );
    }
    Ok(facets)
}

fn parse_ascii(bytes: &[u8], origin: &str) -> Result<Facets, StlError> {
    let text = std::str::from_utf8(bytes).map_err(|e| StlError::Malformed {
        origin: origin.to_owned(),
        line: 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count(),
        message: "not UTF-8 text".to_owned(),
    })?;
    let err = |line: usize, message: String| StlError::Malformed {
        origin: origin.to_owned(),
        line,
        message,
    };
    #[derive(PartialEq, Clone, Copy)]
    enum State {
        /// Expecting `solid`.
        Start,
        /// Inside a solid: `facet` or `endsolid`.
        Solid,
        /// After `facet normal`: `outer loop`.
        Facet,
        /// Inside a loop: `vertex` or `endloop`.
        Loop,
        /// After `endloop`: `endfacet`.
        EndLoop,
        /// After `endsolid`: another `solid` or the end.
        Done,
    }
    // Three numbers and nothing else from `toks`.
    let parse_xyz = |line: usize,
                     what: &str,
                     toks: &mut std::str::SplitAsciiWhitespace<'_>|
     -> Result<Vector3<f64>, StlError> {
        let mut v = [0.0; 3];
        let mut count = 0;
        for tok in toks {
            if count < 3 {
                v[count] = tok
                    .parse::<f64>()
                    .map_err(|_| err(line, format!("`{tok}` in `{what}` is not a number")))?;
            }
            count += 1;
        }
        if count != 3 {
            return Err(err(
                line,
                format!("`{what}` needs 3 numbers, found {count}"),
            ));
        }
        Ok(Vector3::new(v[0], v[1], v[2]))
    };
    // True when `tok` is `word`, any case.
    let is = |tok: Option<&str>, word: &str| tok.is_some_and(|t| t.eq_ignore_ascii_case(word));
    let mut state = State::Start;
    let mut facets = Facets::with_capacity(bytes.len() / 250);
    let mut normal = Vector3::zeros();
    let mut verts: [Point3<f64>; 3] = [Point3::origin(); 3];
    let mut n_verts = 0;
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        last_line = line;
        let mut toks = raw.split_ascii_whitespace();
        let Some(first) = toks.next() else {
            continue;
        };
        let kw = Keyword::of(first);
        match (state, kw) {
            (State::Start | State::Done, Keyword::Solid) => state = State::Solid,
            (State::Solid, Keyword::Facet) => {
                if !is(toks.next(), "normal") {
                    return Err(err(line, "expected `facet normal nx ny nz`".to_owned()));
                }
                normal = parse_xyz(line, "facet normal", &mut toks)?;
                state = State::Facet;
            }
            (State::Solid, Keyword::EndSolid) => state = State::Done,
            (State::Facet, Keyword::Outer) => {
                if !is(toks.next(), "loop") || toks.next().is_some() {
                    return Err(err(line, "expected `outer loop`".to_owned()));
                }
                n_verts = 0;
                state = State::Loop;
            }
            (State::Loop, Keyword::Vertex) => {
                if n_verts == 3 {
                    return Err(err(
                        line,
                        "more than 3 vertices in a facet (only triangles are allowed)".to_owned(),
                    ));
                }
                verts[n_verts] = Point3::from(parse_xyz(line, "vertex", &mut toks)?);
                n_verts += 1;
            }
            (State::Loop, Keyword::EndLoop) => {
                if n_verts != 3 {
                    return Err(err(line, format!("facet has {n_verts} vertices, needs 3")));
                }
                state = State::EndLoop;
            }
            (State::EndLoop, Keyword::EndFacet) => {
                facets.push(normal, verts);
                state = State::Solid;
            }
            (s, _) => {
                let expected = match s {
                    State::Start => "`solid`",
                    State::Solid => "`facet` or `endsolid`",
                    State::Facet => "`outer loop`",
                    State::Loop => "`vertex` or `endloop`",
                    State::EndLoop => "`endfacet`",
                    State::Done => "`solid` or the end of the file",
                };
                return Err(err(line, format!("expected {expected}, found `{first}`")));
            }
        }
    }
    match state {
        State::Done => {}
        // Tolerate a missing `endsolid` after complete facets.
        State::Solid if !facets.is_empty() => {}
        _ => {
            return Err(err(
                last_line,
                "file ends inside a solid (missing `endfacet`/`endsolid`)".to_owned(),
            ));
        }
    }
    Ok(facets)
}

/// The first word of an ASCII STL line, any case.
#[derive(Clone, Copy, PartialEq)]
enum Keyword {
    Solid,
    Facet,
    Outer,
    Vertex,
    EndLoop,
    EndFacet,
    EndSolid,
    Other,
}

impl Keyword {
    fn of(word: &str) -> Self {
        const WORDS: [(&str, Keyword); 7] = [
            ("vertex", Keyword::Vertex),
            ("facet", Keyword::Facet),
            ("outer", Keyword::Outer),
            ("endloop", Keyword::EndLoop),
            ("endfacet", Keyword::EndFacet),
            ("solid", Keyword::Solid),
            ("endsolid", Keyword::EndSolid),
        ];
        WORDS
            .iter()
            .find(|(w, _)| w.eq_ignore_ascii_case(word))
            .map_or(Keyword::Other, |&(_, k)| k)
    }
}

/// Welds, drops degenerate facets, orients by the stored normals and builds the mesh.
fn build_mesh(
    facets: &Facets,
    origin: &str,
    name: &str,
) -> Result<(PanelMesh, StlReport), StlError> {
    if facets.is_empty() {
        return Err(StlError::NoFacets {
            origin: origin.to_owned(),
        });
    }
    let points = &facets.points;
    if let Some(bad) = points
        .iter()
        .position(|v| !(v.x.is_finite() && v.y.is_finite() && v.z.is_finite()))
    {
        return Err(StlError::NonFinite {
            origin: origin.to_owned(),
            facet: bad / 3,
        });
    }
    let (lo, hi) = bounding_box_of(points);
    let diag = (hi - lo).norm();
    let (vertices, map) = weld_vertices(points, diag * WELD_TOLERANCE_RELATIVE);
    let min_twice_area = 2.0 * (diag * 1e-10).powi(2);
    let mut report = StlReport {
        facets_read: facets.len(),
        ..StlReport::default()
    };
    let mut triangles = Vec::with_capacity(facets.len());
    for (i, stored) in facets.normals.iter().enumerate() {
        let [a, b, c] = [map[3 * i], map[3 * i + 1], map[3 * i + 2]];
        let cross = (vertices[b] - vertices[a]).cross(&(vertices[c] - vertices[a]));
        if a == b || b == c || a == c || cross.norm() <= min_twice_area {
            report.degenerate_dropped += 1;
            continue;
        }
        // A zero or non-finite stored normal carries no orientation; keep the winding then.
        if stored.iter().all(|x| x.is_finite()) && cross.dot(stored) < 0.0 {
            report.reoriented += 1;
            triangles.push([a, c, b]);
        } else {
            triangles.push([a, b, c]);
        }
    }
    if triangles.is_empty() {
        return Err(StlError::AllDegenerate {
            origin: origin.to_owned(),
            facets: facets.len(),
        });
    }
    // Keep only the vertices the kept triangles use.
    let mut used = vec![usize::MAX; vertices.len()];
    let mut kept = Vec::with_capacity(vertices.len());
    for t in &mut triangles {
        for v in t.iter_mut() {
            if used[*v] == usize::MAX {
                used[*v] = kept.len();
                kept.push(vertices[*v]);
            }
            *v = used[*v];
        }
    }
    report.vertices = kept.len();
    let mesh = PanelMesh::from_triangles(kept, &triangles, Surface::new(name, RegionKind::Other))
        .map_err(|source| StlError::Mesh {
        origin: origin.to_owned(),
        source,
    })?;
    Ok((mesh, report))
}

/// Triangles of a mesh: quads split along the (0, 2) diagonal.
fn mesh_triangles(mesh: &PanelMesh) -> impl Iterator<Item = [Point3<f64>; 3]> + '_ {
    mesh.panels.iter().flat_map(move |p| {
        let v = |k: usize| mesh.vertices[p.vertices[k]];
        let first = [v(0), v(1), v(2)];
        let second = (p.vertex_count == 4).then(|| [v(0), v(2), v(3)]);
        std::iter::once(first).chain(second)
    })
}

fn unit_normal(t: &[Point3<f64>; 3]) -> Vector3<f64> {
    (t[1] - t[0])
        .cross(&(t[2] - t[0]))
        .try_normalize(0.0)
        .unwrap_or_else(Vector3::zeros)
}

/// Binary STL bytes of `mesh` (quads split into two triangles); `header` goes in the 80-byte
/// header, truncated.
pub fn stl_binary_bytes(mesh: &PanelMesh, header: &str) -> Vec<u8> {
    let tris: Vec<[Point3<f64>; 3]> = mesh_triangles(mesh).collect();
    let mut out = Vec::with_capacity(84 + 50 * tris.len());
    let mut head = [b' '; 80];
    for (slot, b) in head.iter_mut().zip(header.bytes()) {
        *slot = b;
    }
    out.extend_from_slice(&head);
    let n = u32::try_from(tris.len()).unwrap_or(u32::MAX);
    out.extend_from_slice(&n.to_le_bytes());
    for t in tris.iter().take(n as usize) {
        let normal = unit_normal(t);
        for v in std::iter::once(normal).chain(t.iter().map(|p| p.coords)) {
            for x in v.iter() {
                out.extend_from_slice(&(*x as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// ASCII STL text of `mesh` (quads split into two triangles) as solid `name`.
pub fn stl_ascii_string(mesh: &PanelMesh, name: &str) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(s, "solid {name}");
    for t in mesh_triangles(mesh) {
        let n = unit_normal(&t);
        let _ = writeln!(s, "  facet normal {:e} {:e} {:e}", n.x, n.y, n.z);
        let _ = writeln!(s, "    outer loop");
        for v in &t {
            let _ = writeln!(s, "      vertex {:e} {:e} {:e}", v.x, v.y, v.z);
        }
        let _ = writeln!(s, "    endloop");
        let _ = writeln!(s, "  endfacet");
    }
    let _ = writeln!(s, "endsolid {name}");
    s
}

/// Writes `mesh` as a binary STL (quads split into two triangles).
pub fn write_stl_binary(mesh: &PanelMesh, path: &Path) -> Result<(), StlError> {
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let bytes = stl_binary_bytes(mesh, &format!("hsv binary STL {name}"));
    std::fs::write(path, bytes).map_err(|source| StlError::Io {
        origin: path.display().to_string(),
        action: "write",
        source,
    })
}

/// Writes `mesh` as an ASCII STL (quads split into two triangles).
pub fn write_stl_ascii(mesh: &PanelMesh, path: &Path) -> Result<(), StlError> {
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    std::fs::write(path, stl_ascii_string(mesh, &name)).map_err(|source| StlError::Io {
        origin: path.display().to_string(),
        action: "write",
        source,
    })
}
