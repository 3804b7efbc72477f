//! Fixtures for tests and benches across the workspace: the embedded sample vehicle's regions and
//! registries, built once per process.

use std::collections::BTreeMap;
use std::sync::{Mutex, OnceLock};

use crate::config::LoadedConfig;
use crate::region::RegionInfo;
use crate::registry::Registry;

/// Region `name` of the embedded sample vehicle (`main_body`, `left_surface`, `right_surface`,
/// `propulsion`). Panics on an unknown name: fixtures are for tests.
pub fn sample_region(name: &str) -> &'static RegionInfo {
    static REGIONS: OnceLock<Mutex<BTreeMap<String, &'static RegionInfo>>> = OnceLock::new();
    let mut regions = REGIONS
        .get_or_init(|| Mutex::new(BTreeMap::new()))
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    regions.entry(name.to_owned()).or_insert_with(|| {
        let loaded = LoadedConfig::sample().expect("the embedded sample config parses");
        let region = loaded
            .region(name)
            .unwrap_or_else(|e| panic!("sample region `{name}`: {e}"));
        Box::leak(Box::new(region))
    })
}

/// The vertical fin of the sample config's commented `[vertical_fin]` block (between its
/// `>>> vertical fin` and `<<< vertical fin` markers), uncommented and parsed.
pub fn sample_vertical_fin() -> crate::geometry::VerticalFinConfig {
    let text = crate::config::SAMPLE_CONFIG_TOML;
    let start = text
        .find("#[vertical_fin]\n")
        .expect("the sample's fin block");
    let end = start
        + text[start..]
            .find("\n#\n")
            .expect("the end of the fin table");
    let table: String = text[start..end]
        .lines()
        .skip(1)
        .map(|line| format!("{}\n", &line[1..]))
        .collect();
    toml::from_str(&table).expect("the sample's fin table parses")
}

/// An empty registry, for contexts of models that build no base models.
pub fn empty_registry() -> &'static Registry {
    static EMPTY: OnceLock<Registry> = OnceLock::new();
    EMPTY.get_or_init(Registry::empty)
}

/// Every model linked into the calling binary.
pub fn builtin_registry() -> &'static Registry {
    static BUILTIN: OnceLock<Registry> = OnceLock::new();
    BUILTIN.get_or_init(|| Registry::builtin().expect("built-in models register"))
}

/// A global allocator that counts this thread's heap allocations, to check that a time loop or
/// solver allocates nothing. Install it in a test binary with
/// `#[global_allocator] static GLOBAL: CountingAllocator = CountingAllocator;` and compare
/// [`allocations`] before and after the call.
pub struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

// SAFETY: every call forwards to the system allocator unchanged; the counter is a thread-local
// `Cell` that never allocates.
unsafe impl std::alloc::GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { std::alloc::System.realloc(ptr, layout, new_size) }
    }
}

/// Heap allocations made on this thread so far under [`CountingAllocator`].
pub fn allocations() -> usize {
    ALLOCATIONS.with(std::cell::Cell::get)
}

/// Pairs (upper panel, lower panel) of a lifting-surface mesh whose centroids coincide in the
/// planform: the mirror images about its mid-plane, for symmetry checks. Panels with a nearly
/// vertical normal (|n_z| > 0.5) only. Panics when a lower panel has no mirror (the mesh is
/// not symmetric, so no symmetry check on it could pass).
pub fn mirror_panel_pairs(mesh: &crate::mesh::PanelMesh) -> Vec<(usize, usize)> {
    let faces = |sign: f64| -> Vec<usize> {
        (0..mesh.panels.len())
            .filter(|&i| sign * mesh.panels[i].normal.z > 0.5)
            .collect()
    };
    let lower = faces(1.0);
    let pairs: Vec<(usize, usize)> = faces(-1.0)
        .into_iter()
        .filter_map(|u| {
            let c = mesh.panels[u].centroid;
            lower
                .iter()
                .find(|&&l| {
                    let d = mesh.panels[l].centroid - c;
                    d.x.hypot(d.y) < 1e-9
                })
                .map(|&l| (u, l))
        })
        .collect();
    assert_eq!(pairs.len(), lower.len(), "every lower panel has its mirror");
    pairs
}

/// The cdylib of example plugin crate `crate_name` (`hsv_plugin_ackeret`, ...): built as a
/// dev-dependency of the calling test crate, so it sits in `target/<profile>/deps/` next to the
/// test binary (or one level up after `cargo build`). Panics when it is missing.
pub fn plugin_path(crate_name: &str) -> std::path::PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    let deps_dir = exe.parent().expect("target/<profile>/deps/<test>");
    let file = format!(
        "{}{crate_name}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    let candidates = [deps_dir.join(&file), deps_dir.join("..").join(&file)];
    candidates
        .iter()
        .find(|path| path.exists())
        .cloned()
        .unwrap_or_else(|| panic!("{file} not found next to {}", deps_dir.display()))
}
