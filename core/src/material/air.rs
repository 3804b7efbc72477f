//! Still air, a thermal-only material for the hollow interior of a built-up lifting surface
//! (k, c_p and density; no E or α, so a structure model refuses it and only the conduction
//! models use it).
//!
//! **`air`**: dry air at atmospheric pressure, Table A.4 "Thermophysical properties of gases at
//! atmospheric pressure" of Incropera & DeWitt, Fundamentals of Heat and Mass Transfer (7th ed.:
//! Bergman, Lavine, Incropera & DeWitt, Wiley 2011): k and c_p at its 35 temperatures,
//! 100-3000 K, used as tabulated (linear between rows). The rows were read from open
//! transcriptions of the table (the k column as in `byutpl`, T. A. Knotts IV,
//! github.com/thomasknotts/byutpl, `properties/air.py`, which cites that edition; the c_p
//! column from two further transcriptions that agree with each other row for row).
//!
//! **Still.** Only conduction through the gas: no convection (free convection in a closed
//! cavity would add to it) and no radiation between the faces around it. The conduction models
//! neglect both, which makes an air-filled interior nearly adiabatic.
//!
//! **Pressure.** The conductivity of a gas does not depend on its pressure while the gap is
//! many mean free paths wide: at 26.5 kPa (10 km) and 1000 K the mean free path is 0.9 μm
//! (see `insulation.rs`), against interiors of millimetres to centimetres.
//!
//! **Density.** A material's density is one number: the table's 300 K, 1 atm value,
//! 1.1614 kg/m³ (a sealed interior keeps the mass it was closed with, whatever its temperature;
//! a vented one at altitude holds less). The interior's heat capacity is negligible either way:
//! ρ c_p ≈ 1.2 kJ/(m³ K) against 2.4 MJ/(m³ K) for Ti-6Al-4V, and the table's c_p (constant
//! pressure) rather than c_v of a sealed cavity does not change that.
//!
//! **Melting point.** Air has none; the field only bounds the table, so it is set just above the
//! last row.

use super::{Material, MaterialPoint};

/// Incropera & DeWitt Table A.4, air at 1 atm: (T K, k W/(m K), c_p J/(kg K)), 100-3000 K.
const AIR_ROWS: [(f64, f64, f64); 35] = [
    (100.0, 0.00934, 1032.0),
    (150.0, 0.0138, 1012.0),
    (200.0, 0.0181, 1007.0),
    (250.0, 0.0223, 1006.0),
    (300.0, 0.0263, 1007.0),
    (350.0, 0.0300, 1009.0),
    (400.0, 0.0338, 1014.0),
    (450.0, 0.0373, 1021.0),
    (500.0, 0.0407, 1030.0),
    (550.0, 0.0439, 1040.0),
    (600.0, 0.0469, 1051.0),
    (650.0, 0.0497, 1063.0),
    (700.0, 0.0524, 1075.0),
    (750.0, 0.0549, 1087.0),
    (800.0, 0.0573, 1099.0),
    (850.0, 0.0596, 1110.0),
    (900.0, 0.0620, 1121.0),
    (950.0, 0.0643, 1131.0),
    (1000.0, 0.0667, 1141.0),
    (1100.0, 0.0715, 1159.0),
    (1200.0, 0.0763, 1175.0),
    (1300.0, 0.082, 1189.0),
    (1400.0, 0.091, 1207.0),
    (1500.0, 0.100, 1230.0),
    (1600.0, 0.106, 1248.0),
    (1700.0, 0.113, 1267.0),
    (1800.0, 0.120, 1286.0),
    (1900.0, 0.128, 1307.0),
    (2000.0, 0.137, 1337.0),
    (2100.0, 0.147, 1372.0),
    (2200.0, 0.160, 1417.0),
    (2300.0, 0.175, 1478.0),
    (2400.0, 0.196, 1558.0),
    (2500.0, 0.222, 1665.0),
    (3000.0, 0.486, 2726.0),
];

/// Density of air at 300 K and 1 atm, kg/m³ (Incropera & DeWitt Table A.4; module docs).
pub const AIR_DENSITY_KG_M3: f64 = 1.1614;

/// Bound in place of a melting point, K: just above the table's last row (module docs).
const TABLE_BOUND_K: f64 = 3001.0;

impl Material {
    /// Still air at atmospheric pressure, thermal only, 100-3000 K (Incropera & DeWitt Table A.4;
    /// sources, density and what "still" leaves out in the module docs of `air.rs`). No
    /// mechanical data: Poisson's ratio is NaN and [`Material::at`] is an error, so it can fill
    /// the interior of a built-up structure in the conduction models but not be a structure.
    pub fn air() -> Self {
        Self {
            name: "air (still, 1 atm)".to_owned(),
            density_kg_m3: AIR_DENSITY_KG_M3,
            poisson_ratio: f64::NAN,
            melting_point_k: TABLE_BOUND_K,
            table: AIR_ROWS
                .iter()
                .map(|&(t, k, c)| MaterialPoint::thermal_only(t, k, c))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Incropera & DeWitt Table A.4 rows exactly (spot checks of the transcription: 300 K
    /// 26.3e-3 W/(m K) and 1007 J/(kg K), 1000 K 66.7e-3 and 1141, 3000 K 486e-3 and 2726),
    /// linear between them.
    #[test]
    fn air_reproduces_incropera_table_a4() {
        let m = Material::air();
        m.validate().expect("valid");
        for (t, k, c) in AIR_ROWS {
            assert_relative_eq!(m.conductivity_w_m_k(t).unwrap(), k, max_relative = 1e-12);
            assert_relative_eq!(m.specific_heat_j_kg_k(t).unwrap(), c, max_relative = 1e-12);
        }
        for (t, k, c) in [
            (300.0, 0.0263, 1007.0),
            (1000.0, 0.0667, 1141.0),
            (3000.0, 0.486, 2726.0),
        ] {
            assert_eq!(m.conductivity_w_m_k(t).unwrap(), k);
            assert_eq!(m.specific_heat_j_kg_k(t).unwrap(), c);
        }
        // Midway between 500 and 550 K.
        assert_relative_eq!(
            m.conductivity_w_m_k(525.0).unwrap(),
            0.5 * (0.0407 + 0.0439),
            max_relative = 1e-12
        );
        assert_eq!(m.density_kg_m3, 1.1614);
        assert_eq!(m.temperature_range_k(), (100.0, 3000.0));
        assert!(m.conductivity_w_m_k(99.0).is_err());
        assert!(m.specific_heat_j_kg_k(3000.5).is_err());
    }

    /// Against an independent compilation, the "Properties of air at 1 atm pressure" table of
    /// Çengel's textbook appendices (as reproduced by engineersedge.com): at 25, 100 and
    /// 160 °C, k = 0.02551, 0.03095, 0.03511 W/(m K) and c_p = 1007, 1009, 1016 J/(kg K).
    /// Incropera's k lies 2.5-2.9 % above (3 % tolerance), c_p within 0.3 % (0.5 % tolerance).
    #[test]
    fn air_agrees_with_cengel_near_room_temperature() {
        let m = Material::air();
        for (t, k, c) in [
            (298.15, 0.02551, 1007.0),
            (373.15, 0.03095, 1009.0),
            (433.15, 0.03511, 1016.0),
        ] {
            assert_relative_eq!(m.conductivity_w_m_k(t).unwrap(), k, max_relative = 0.03);
            assert_relative_eq!(m.specific_heat_j_kg_k(t).unwrap(), c, max_relative = 0.005);
        }
    }

    /// The interior's heat capacity per volume is three orders of magnitude below the
    /// titanium's at 300 K (module docs: negligible).
    #[test]
    fn air_heat_capacity_is_negligible_beside_titanium() {
        let air = Material::air();
        let ti = Material::ti_6al_4v();
        let air_c = air.density_kg_m3 * air.specific_heat_j_kg_k(300.0).unwrap();
        let ti_c = ti.density_kg_m3 * ti.specific_heat_j_kg_k(300.0).unwrap();
        assert!(air_c < 1e-3 * ti_c, "{air_c} vs {ti_c} J/(m³ K)");
    }

    /// A thermal-only material: no E or α, and asking for them names the material; found by name.
    #[test]
    fn air_has_no_mechanical_data_and_is_built_in() {
        let m = Material::air();
        assert!(m.table.iter().all(|r| r.youngs_modulus_pa.is_none()));
        let err = m.youngs_modulus_pa(300.0).unwrap_err().to_string();
        assert!(
            err.contains("air") && err.contains("no mechanical data"),
            "{err}"
        );
        assert_eq!(
            Material::by_name("Air").unwrap().table,
            Material::air().table
        );
        assert!(crate::material::BUILTIN_MATERIALS.contains(&"air"));
    }
}
