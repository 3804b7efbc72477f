//! Vertex welding: points closer than a tolerance merged with a uniform hash grid (STL files
//! repeat every shared vertex), and the fast integer-keyed hash map the mesh's edge checks use.

use super::*;

/// FxHash (the rustc hasher): one multiply-rotate per word. Keys here are integers built from
/// coordinates and indices, not attacker-chosen, so SipHash's DoS resistance buys nothing and
/// costs most of an STL read.
#[derive(Default, Clone, Copy)]
pub(super) struct FxHasher(u64);

impl std::hash::Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
    fn write_u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_usize(&mut self, word: usize) {
        self.write_u64(word as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

pub(super) type FastMap<K, V> = HashMap<K, V, std::hash::BuildHasherDefault<FxHasher>>;

pub(super) fn fast_map<K, V>(capacity: usize) -> FastMap<K, V> {
    FastMap::with_capacity_and_hasher(capacity, Default::default())
}

/// Merges points closer than `tolerance_m` (first come, first kept) with a uniform hash grid.
///
/// Returns the unique points and, for each input point, its index among them. Bit-identical
/// copies (the usual duplicates of an STL file) are merged first by one hash lookup each; the
/// distinct points then go through a grid of cells 2 × tolerance wide, where a point's
/// neighbours within the tolerance lie in the 2 × 2 × 2 cells on its nearer sides.
pub fn weld_vertices(points: &[Point3<f64>], tolerance_m: f64) -> (Vec<Point3<f64>>, Vec<usize>) {
    let tol = if tolerance_m.is_finite() && tolerance_m > 0.0 {
        tolerance_m
    } else {
        0.0
    };
    let (distinct, mut map) = merge_identical(points);
    if tol == 0.0 {
        return (distinct, map);
    }
    let cell = 2.0 * tol;
    // `as` saturates for huge values, which only coarsens the grid there.
    let cell_of = |x: f64| (x / cell).floor() as i64;
    // Cell key -> first point in it; `next` chains the points of a cell.
    let mut heads: FastMap<(i64, i64, i64), usize> = fast_map(distinct.len());
    let mut next = vec![usize::MAX; distinct.len()];
    let mut unique: Vec<Point3<f64>> = Vec::with_capacity(distinct.len());
    let mut renumber = Vec::with_capacity(distinct.len());
    let tol2 = tol * tol;
    for p in &distinct {
        let c = [cell_of(p.x), cell_of(p.y), cell_of(p.z)];
        // The neighbour cell on the side of the nearer cell face.
        let side = |x: f64, c: i64| {
            if x - c as f64 * cell < tol {
                c.saturating_sub(1)
            } else {
                c.saturating_add(1)
            }
        };
        let n = [side(p.x, c[0]), side(p.y, c[1]), side(p.z, c[2])];
        let mut found = None;
        'search: for x in [c[0], n[0]] {
            for y in [c[1], n[1]] {
                for z in [c[2], n[2]] {
                    let mut id = heads.get(&(x, y, z)).copied().unwrap_or(usize::MAX);
                    while id != usize::MAX {
                        if (unique[id] - p).norm_squared() <= tol2 {
                            found = Some(id);
                            break 'search;
                        }
                        id = next[id];
                    }
                }
            }
        }
        let id = found.unwrap_or_else(|| {
            let id = unique.len();
            unique.push(*p);
            if let Some(head) = heads.insert((c[0], c[1], c[2]), id) {
                next[id] = head;
            }
            id
        });
        renumber.push(id);
    }
    for m in &mut map {
        *m = renumber[*m];
    }
    (unique, map)
}

/// Bit-identical points merged (first kept): the distinct points and each input's index.
///
/// An open-addressing table of 4-byte slots (index + 1, 0 = empty) at most half full, probed
/// linearly: small enough to stay in cache for a few hundred thousand points, which a map of
/// full keys is not.
fn merge_identical(points: &[Point3<f64>]) -> (Vec<Point3<f64>>, Vec<usize>) {
    let Some(slots) = (2 * points.len())
        .max(16)
        .checked_next_power_of_two()
        .filter(|_| points.len() < u32::MAX as usize)
    else {
        return merge_identical_large(points);
    };
    let bits = |p: &Point3<f64>| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    let shift = 64 - slots.trailing_zeros();
    let mut table = vec![0u32; slots];
    let mut distinct: Vec<Point3<f64>> = Vec::with_capacity(points.len() / 2);
    let mut map = Vec::with_capacity(points.len());
    for p in points {
        let key = bits(p);
        let mut hasher = FxHasher::default();
        std::hash::Hash::hash(&key, &mut hasher);
        // The top bits of the Fx product are the well-mixed ones.
        let mut slot = (std::hash::Hasher::finish(&hasher) >> shift) as usize;
        let id = loop {
            match table[slot] {
                0 => {
                    distinct.push(*p);
                    // At most u32::MAX - 1 points (checked above), so this fits.
                    table[slot] = distinct.len() as u32;
                    break distinct.len() - 1;
                }
                stored if bits(&distinct[stored as usize - 1]) == key => {
                    break stored as usize - 1;
                }
                _ => slot = (slot + 1) & (slots - 1),
            }
        };
        map.push(id);
    }
    (distinct, map)
}

/// [`merge_identical`] for more points than 4-byte slots can number.
fn merge_identical_large(points: &[Point3<f64>]) -> (Vec<Point3<f64>>, Vec<usize>) {
    let mut seen: FastMap<(u64, u64, u64), usize> = fast_map(points.len() / 2);
    let mut distinct = Vec::with_capacity(points.len() / 2);
    let map = points
        .iter()
        .map(|p| {
            let key = (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
            *seen.entry(key).or_insert_with(|| {
                distinct.push(*p);
                distinct.len() - 1
            })
        })
        .collect();
    (distinct, map)
}
