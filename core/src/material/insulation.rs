//! Thermal-only insulating materials for thermal-protection layers (k, c_p and density; no E or
//! α, so a structure model refuses them and only the conduction models use them).
//!
//! **`vdi-l1400`**: the lightweight insulating refractory brick "L1400" of the VDI Heat Atlas
//! refractory table (VDI-Gesellschaft, VDI Heat Atlas, 2nd ed., Springer 2010), as transcribed
//! in the `refractories` table of the open `ht` library (C. Bell, github.com/CalebBell/ht,
//! `ht/insulation.py`, which cites that edition): density 790 kg/m³, k and c_p at 400, 600,
//! 800, 1000 and 1200 °C. The label's number is the brick's classification temperature in °C
//! (our reading of the naming shared by the table's L1260 … L1870 rows).
//!
//! **Outside the tabulated 673.15-1473.15 K** (our choice, two rows, marked below): the layer
//! starts at 293 K and its outer face reaches about 1515 K at Mach 6, 10 km, so the table needs
//! rows beyond the data.
//! - 293 K: the 673.15 K values held (as `ht` clamps). k rises with T in the data, so holding
//!   overestimates k below 673 K (more heat reaches the structure: conservative); c_p rises too,
//!   so it is overestimated, by at most 8 % (77 J/(kg K)) if the first interval's slope went on.
//! - 1673.15 K (1400 °C, the classification temperature): the last interval (1273.15-1473.15 K)
//!   continued linearly, k 0.38 W/(m K), c_p 1066 J/(kg K).
//!   On the sample surface at Mach 6, 10 km, 100 s with a 2 mm layer, replacing either choice by
//!   the other (linear continuation below, hold above) moves the structure's largest
//!   temperature by 0.9 K and 0.0 K (1168.4 K).
//!
//! **Pressure.** VDI tabulates refractories for furnace use, in air at atmospheric pressure (the
//! pressure is not stated in the transcription; this is our reading). At 10 km the layer is
//! vented to at least the freestream 26.5 kPa (US Standard Atmosphere 1976), where the mean free
//! path of air, λ = k_B T / (√2 π d² p) (d = 3.7e-10 m), is 0.9 μm at 1000 K and 1.3 μm at
//! 1500 K: in pores larger than about 10 μm (Kn < 0.1) gas conduction is in the continuum
//! regime and independent of pressure, so the atmospheric values apply.
//!
//! **Melting point.** 1860 K, the lowest solidus of the Al₂O₃-SiO₂ system (the silica-mullite
//! eutectic, 1587 °C; Klug, Prochazka & Doremus, J. Am. Ceram. Soc. 70 (1987) 750-759): VDI
//! gives no composition; insulating firebricks are alumino-silicates (our assumption). It only
//! bounds the table (every row lies below it).

use super::{Material, MaterialPoint};

/// VDI Heat Atlas L1400 rows: (T K, k W/(m K), c_p J/(kg K)), 400-1200 °C.
const VDI_L1400_ROWS: [(f64, f64, f64); 5] = [
    (673.15, 0.27, 954.0),
    (873.15, 0.30, 994.0),
    (1073.15, 0.32, 1018.0),
    (1273.15, 0.34, 1034.0),
    (1473.15, 0.36, 1050.0),
];

/// Bulk density of L1400, kg/m³ (VDI Heat Atlas, as transcribed in `ht`).
pub const VDI_L1400_DENSITY_KG_M3: f64 = 790.0;

/// Our choice below the data: the 673.15 K row held at 293 K (module docs).
const HELD_FLOOR_K: f64 = 293.0;

/// Our choice above the data: the last interval continued to 1673.15 K (module docs).
const CONTINUED_CEILING_K: f64 = 1673.15;

/// Lowest solidus of Al₂O₃-SiO₂ (silica-mullite eutectic, 1587 °C), K (module docs).
const ALUMINOSILICATE_SOLIDUS_K: f64 = 1860.0;

/// y on the line through the last two data rows at `temperature_k` (linear continuation).
fn continued(temperature_k: f64, value: impl Fn(&(f64, f64, f64)) -> f64) -> f64 {
    let (a, b) = (&VDI_L1400_ROWS[3], &VDI_L1400_ROWS[4]);
    value(b) + (value(b) - value(a)) * (temperature_k - b.0) / (b.0 - a.0)
}

impl Material {
    /// VDI Heat Atlas lightweight insulating refractory L1400, thermal only, 293-1673.15 K
    /// (data 673.15-1473.15 K; sources and the two rows beyond the data in the module docs of
    /// `insulation.rs`). No mechanical data: Poisson's ratio is NaN and [`Material::at`] is an
    /// error, so it can be a conduction layer (`layers = [{ material = "vdi-l1400", … }]`) but
    /// not a structure.
    pub fn vdi_l1400() -> Self {
        let (_, k0, c0) = VDI_L1400_ROWS[0];
        let data = VDI_L1400_ROWS
            .iter()
            .map(|&(t, k, c)| MaterialPoint::thermal_only(t, k, c));
        let top = MaterialPoint::thermal_only(
            CONTINUED_CEILING_K,
            continued(CONTINUED_CEILING_K, |r| r.1),
            continued(CONTINUED_CEILING_K, |r| r.2),
        );
        Self {
            name: "VDI L1400 insulating refractory".to_owned(),
            density_kg_m3: VDI_L1400_DENSITY_KG_M3,
            poisson_ratio: f64::NAN,
            melting_point_k: ALUMINOSILICATE_SOLIDUS_K,
            table: std::iter::once(MaterialPoint::thermal_only(HELD_FLOOR_K, k0, c0))
                .chain(data)
                .chain(std::iter::once(top))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The five VDI Heat Atlas rows (as transcribed in `ht`) exactly, linear between them.
    #[test]
    fn l1400_reproduces_the_vdi_rows() {
        let m = Material::vdi_l1400();
        m.validate().expect("valid");
        for (t, k, c) in VDI_L1400_ROWS {
            assert_relative_eq!(m.conductivity_w_m_k(t).unwrap(), k, max_relative = 1e-12);
            assert_relative_eq!(m.specific_heat_j_kg_k(t).unwrap(), c, max_relative = 1e-12);
        }
        // Midway between 800 and 1000 °C.
        assert_relative_eq!(
            m.conductivity_w_m_k(1173.15).unwrap(),
            0.33,
            max_relative = 1e-12
        );
        assert_eq!(m.density_kg_m3, 790.0);
        assert_eq!(m.temperature_range_k(), (293.0, 1673.15));
    }

    /// The rows beyond the data are what the module docs say: the 400 °C values held at 293 K,
    /// the last interval's slope continued to 1400 °C (0.01 W/(m K) and 8 J/(kg K) per 100 K).
    #[test]
    fn l1400_rows_beyond_the_data_are_the_documented_choices() {
        let m = Material::vdi_l1400();
        assert_eq!(m.conductivity_w_m_k(293.0).unwrap(), 0.27);
        assert_eq!(m.specific_heat_j_kg_k(293.0).unwrap(), 954.0);
        assert_relative_eq!(
            m.conductivity_w_m_k(1673.15).unwrap(),
            0.38,
            max_relative = 1e-12
        );
        assert_relative_eq!(
            m.specific_heat_j_kg_k(1673.15).unwrap(),
            1066.0,
            max_relative = 1e-12
        );
        assert!(m.conductivity_w_m_k(1673.2).is_err());
        assert!(m.conductivity_w_m_k(292.0).is_err());
    }

    /// Specific heat is a mass property of the solid and does not depend on porosity, so the
    /// porous brick's c_p matches the dense fireclay brick of the same VDI table (956, 997, 1021,
    /// 1037, 1054 J/(kg K) at 400-1200 °C) within 1 % (they differ by 0.2-0.4 %). A consistency
    /// check within one source, not an independent one.
    #[test]
    fn l1400_heat_capacity_matches_the_dense_fireclay_of_the_same_table() {
        let m = Material::vdi_l1400();
        let fireclay = [
            (673.15, 956.0),
            (873.15, 997.0),
            (1073.15, 1021.0),
            (1273.15, 1037.0),
            (1473.15, 1054.0),
        ];
        for (t, c_dense) in fireclay {
            assert_relative_eq!(
                m.specific_heat_j_kg_k(t).unwrap(),
                c_dense,
                max_relative = 1e-2
            );
        }
    }

    /// A thermal-only material: no E or α anywhere, and asking for them names the material and
    /// says it has no mechanical data.
    #[test]
    fn l1400_has_no_mechanical_data() {
        let m = Material::vdi_l1400();
        assert!(m.table.iter().all(|r| r.youngs_modulus_pa.is_none()));
        let err = m.youngs_modulus_pa(800.0).unwrap_err().to_string();
        assert!(
            err.contains("L1400") && err.contains("no mechanical data"),
            "{err}"
        );
        assert!(m.thermal_strain(800.0).is_err());
        assert_eq!(
            Material::by_name("VDI-L1400").unwrap().table,
            Material::vdi_l1400().table
        );
    }
}
