//! Temperature-dependent isotropic structural materials: a property table per material,
//! interpolated linearly in temperature, with the built-in Ti-6Al-4V table and its sources.
//!
//! A [`Material`] holds temperature-independent constants (density, Poisson's ratio, melting
//! point) and a table of rows `(T, E, α_sec, k, c_p)` in strictly increasing temperature.
//! `α_sec` is the **secant** (mean) coefficient of thermal expansion from
//! [`SECANT_REFERENCE_TEMPERATURE_K`] to T, so the free thermal strain is
//! ε_th(T) = α_sec(T) (T − 293 K) ([`Material::thermal_strain`]). Temperatures outside the
//! table are errors naming the range, never extrapolations.
//!
//! A config gives a material by name (`material = "ti-6al-4v"`) or as a full table
//! ([`MaterialSetting`]); see [`Material::by_name`] for the built-in names.

use serde::{Deserialize, Serialize};

use crate::error::ModelError;

/// Temperature from which secant expansion coefficients are measured, K (20 °C).
pub const SECANT_REFERENCE_TEMPERATURE_K: f64 = 293.0;

/// Built-in material names accepted by [`Material::by_name`].
pub const BUILTIN_MATERIALS: &[&str] = &["ti-6al-4v"];

/// One row of a material's property table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialPoint {
    /// Temperature of this row, K.
    pub temperature_k: f64,
    /// Young's modulus, Pa.
    pub youngs_modulus_pa: f64,
    /// Secant (mean) thermal expansion coefficient from 293 K to this temperature, 1/K.
    pub thermal_expansion_per_k: f64,
    /// Thermal conductivity, W/(m K).
    pub conductivity_w_m_k: f64,
    /// Specific heat at constant pressure, J/(kg K).
    pub specific_heat_j_kg_k: f64,
}

/// Properties of a material at one temperature (a table row interpolated to T).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialProperties {
    /// Temperature, K.
    pub temperature_k: f64,
    /// Young's modulus, Pa.
    pub youngs_modulus_pa: f64,
    /// Secant thermal expansion coefficient from 293 K, 1/K.
    pub thermal_expansion_per_k: f64,
    /// Thermal conductivity, W/(m K).
    pub conductivity_w_m_k: f64,
    /// Specific heat, J/(kg K).
    pub specific_heat_j_kg_k: f64,
}

/// A temperature-dependent isotropic material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Name used in messages, e.g. "Ti-6Al-4V".
    pub name: String,
    /// Density, kg/m³ (temperature-independent: thermal expansion changes it by < 1 %).
    pub density_kg_m3: f64,
    /// Poisson's ratio, in (-1, 0.5).
    pub poisson_ratio: f64,
    /// Melting (solidus) temperature, K; every table row must lie below it.
    pub melting_point_k: f64,
    /// Property rows in strictly increasing temperature (at least one).
    pub table: Vec<MaterialPoint>,
}

/// Why a material could not be built or evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// A temperature outside the material's table.
    #[error(
        "material {material}: temperature {temperature_k} K is outside its property table \
         ({min_k} K to {max_k} K)"
    )]
    TemperatureOutOfRange {
        material: String,
        temperature_k: f64,
        min_k: f64,
        max_k: f64,
    },
    /// A non-physical or inconsistent material value.
    #[error("material {material}: {quantity} = {value}: {message}")]
    Invalid {
        material: String,
        quantity: String,
        value: f64,
        message: String,
    },
    /// A material name that is not built in.
    #[error("unknown material `{name}`; built-in materials: {known}; or give a table")]
    UnknownName { name: String, known: String },
}

impl MaterialError {
    /// The same error as a [`ModelError`] of model `model` (out-of-range temperatures become
    /// [`ModelError::OutOfRange`] on the quantity "temperature (K)").
    pub fn into_model_error(self, model: &str) -> ModelError {
        match self {
            MaterialError::TemperatureOutOfRange {
                material,
                temperature_k,
                min_k,
                max_k,
            } => ModelError::out_of_range(
                model,
                &format!("temperature (K) of {material}"),
                temperature_k,
                format!("{min_k} K to {max_k} K, the material's property table"),
            ),
            other => ModelError::inconsistent(model, other.to_string()),
        }
    }
}

/// How a config names a material: a built-in name or a full custom [`Material`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum MaterialSetting {
    /// A name from [`BUILTIN_MATERIALS`].
    Name(String),
    /// A custom table.
    Table(Material),
}

impl Default for MaterialSetting {
    fn default() -> Self {
        MaterialSetting::Name("ti-6al-4v".to_owned())
    }
}

impl MaterialSetting {
    /// The material this setting names, validated.
    pub fn resolve(&self) -> Result<Material, MaterialError> {
        match self {
            MaterialSetting::Name(name) => Material::by_name(name),
            MaterialSetting::Table(material) => {
                material.validate()?;
                Ok(material.clone())
            }
        }
    }
}

/// Ti-6Al-4V table rows: (T K, E GPa, α_sec 1e-6/K, k W/(m K), c_p J/(kg K)).
///
/// - E: linear least-squares fit E = 119.904 − 0.049811 T GPa (T in K) to the dynamic
///   (resonance) moduli of annealed Ti-6Al-4V measured from 296 K to 1108 K by Fukuhara &
///   Sanpei, "Elastic moduli and internal frictions of Inconel 718 and Ti-6Al-4V as a function
///   of temperature", J. Mater. Sci. Lett. 12 (1993) 1122-1124, doi:10.1007/BF00420541
///   (63 points read from the paper's figure, as digitized in the open BELFEM material library;
///   fit rms 0.69 GPa, largest residual 2.1 GPa).
/// - α_sec: mean coefficients from 20 °C to 100, 315 and 650 °C, 8.6, 9.2 and 9.7e-6/K
///   (BT Metals / TIMET Ti-6Al-4V datasheets, "from 20 °C to temperature"), linear in T between
///   them;
///   the 293 K row repeats the 20-100 °C mean.
/// - k: Polev, Zinovyev & Korshunov, High Temperatures 23 (1985) 704-706 (as compiled by
///   K. C. Mills, "Recommended values of thermophysical properties for selected commercial
///   alloys", NPL/ASM 2002, ch. Ti-6Al-4V): 7.05 (297 K), 7.48 (375), 8.80 (473), 10.21 (572),
///   11.40 (673), 12.64 (773), 14.22 (872), 15.54 (974 K) W/(m K), interpolated linearly.
/// - c_p: linear least-squares fit c_p = 481.50 + 0.21935 T J/(kg K) to the α-phase
///   measurements 293-1268 K of Richardson, Hayes, Day & Mills and Bros, Michel & Castanet,
///   J. Thermal Analysis 41 (1994) 7-24 (as compiled by Mills 2002; rms 8.6 J/(kg K)).
///
/// The table stops at 923 K, the highest temperature of the published expansion data.
const TI_6AL_4V_TABLE: [(f64, f64, f64, f64, f64); 8] = [
    (293.0, 105.31, 8.600, 7.05, 545.8),
    (373.0, 101.32, 8.600, 7.47, 563.3),
    (473.0, 96.34, 8.879, 8.80, 585.3),
    (573.0, 91.36, 9.158, 10.22, 607.2),
    (673.0, 86.38, 9.327, 11.41, 629.1),
    (773.0, 81.40, 9.476, 12.64, 651.1),
    (873.0, 76.42, 9.625, 14.23, 673.0),
    (923.0, 73.93, 9.700, 14.88, 684.0),
];

impl Material {
    /// Ti-6Al-4V (annealed), 293-923 K; sources of each column at [`TI_6AL_4V_TABLE`].
    /// Density 4430 kg/m³ (0.160 lb/in³) and Poisson's ratio 0.31: MMPDS / MIL-HDBK-5J
    /// Ti-6Al-4V design properties (section 5.4.1); solidus 1877 K (1604 °C, lower end of the melting range in the
    /// TIMET/BT Metals datasheet).
    pub fn ti_6al_4v() -> Self {
        Self {
            name: "Ti-6Al-4V".to_owned(),
            density_kg_m3: 4430.0,
            poisson_ratio: 0.31,
            melting_point_k: 1877.0,
            table: TI_6AL_4V_TABLE
                .iter()
                .map(|&(t, e_gpa, a_micro, k, cp)| MaterialPoint {
                    temperature_k: t,
                    youngs_modulus_pa: e_gpa * 1e9,
                    thermal_expansion_per_k: a_micro * 1e-6,
                    conductivity_w_m_k: k,
                    specific_heat_j_kg_k: cp,
                })
                .collect(),
        }
    }

    /// A material whose properties do not depend on temperature, valid from `min_k` to
    /// `max_k` (for plate-theory checks and simple studies).
    #[allow(clippy::too_many_arguments)]
    pub fn constant(
        name: &str,
        density_kg_m3: f64,
        poisson_ratio: f64,
        youngs_modulus_pa: f64,
        thermal_expansion_per_k: f64,
        conductivity_w_m_k: f64,
        specific_heat_j_kg_k: f64,
        (min_k, max_k): (f64, f64),
    ) -> Result<Self, MaterialError> {
        let row = |t| MaterialPoint {
            temperature_k: t,
            youngs_modulus_pa,
            thermal_expansion_per_k,
            conductivity_w_m_k,
            specific_heat_j_kg_k,
        };
        let material = Self {
            name: name.to_owned(),
            density_kg_m3,
            poisson_ratio,
            melting_point_k: max_k * (1.0 + 1e-9) + 1e-9,
            table: vec![row(min_k), row(max_k)],
        };
        material.validate()?;
        Ok(material)
    }

    /// A built-in material by name (case-insensitive): see [`BUILTIN_MATERIALS`].
    pub fn by_name(name: &str) -> Result<Self, MaterialError> {
        match name.to_ascii_lowercase().as_str() {
            "ti-6al-4v" | "ti6al4v" | "ti-64" => Ok(Self::ti_6al_4v()),
            _ => Err(MaterialError::UnknownName {
                name: name.to_owned(),
                known: BUILTIN_MATERIALS.join(", "),
            }),
        }
    }

    fn invalid(&self, quantity: &str, value: f64, message: &str) -> MaterialError {
        MaterialError::Invalid {
            material: self.name.clone(),
            quantity: quantity.to_owned(),
            value,
            message: message.to_owned(),
        }
    }

    /// Checks that every value is finite and physical and the table is increasing in T.
    pub fn validate(&self) -> Result<(), MaterialError> {
        let positive = |q: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(self.invalid(q, v, "must be finite and > 0"))
            }
        };
        positive("density_kg_m3", self.density_kg_m3)?;
        positive("melting_point_k", self.melting_point_k)?;
        let nu = self.poisson_ratio;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(self.invalid("poisson_ratio", nu, "must be in (-1, 0.5)"));
        }
        if self.table.is_empty() {
            return Err(self.invalid("table rows", 0.0, "the table needs at least one row"));
        }
        let mut previous = f64::NEG_INFINITY;
        for (i, row) in self.table.iter().enumerate() {
            let t = row.temperature_k;
            positive(&format!("table[{i}].temperature_k"), t)?;
            if t <= previous {
                return Err(self.invalid(
                    &format!("table[{i}].temperature_k"),
                    t,
                    &format!("temperatures must increase strictly (previous row {previous} K)"),
                ));
            }
            if t >= self.melting_point_k {
                return Err(self.invalid(
                    &format!("table[{i}].temperature_k"),
                    t,
                    &format!("must be below the melting point {} K", self.melting_point_k),
                ));
            }
            previous = t;
            positive(
                &format!("table[{i}].youngs_modulus_pa"),
                row.youngs_modulus_pa,
            )?;
            positive(
                &format!("table[{i}].conductivity_w_m_k"),
                row.conductivity_w_m_k,
            )?;
            positive(
                &format!("table[{i}].specific_heat_j_kg_k"),
                row.specific_heat_j_kg_k,
            )?;
            let a = row.thermal_expansion_per_k;
            if !(a.is_finite() && a.abs() < 1e-3) {
                return Err(self.invalid(
                    &format!("table[{i}].thermal_expansion_per_k"),
                    a,
                    "must be finite and |α| < 1e-3 1/K",
                ));
            }
        }
        Ok(())
    }

    /// Lowest and highest table temperature, K.
    pub fn temperature_range_k(&self) -> (f64, f64) {
        let lo = self.table.first().map_or(f64::NAN, |r| r.temperature_k);
        let hi = self.table.last().map_or(f64::NAN, |r| r.temperature_k);
        (lo, hi)
    }

    /// All properties at `temperature_k`, linear between the bracketing table rows.
    ///
    /// Allocation-free (binary search); an error names the table's range.
    pub fn at(&self, temperature_k: f64) -> Result<MaterialProperties, MaterialError> {
        let (lo, hi) = self.temperature_range_k();
        if !(temperature_k >= lo && temperature_k <= hi) {
            return Err(MaterialError::TemperatureOutOfRange {
                material: self.name.clone(),
                temperature_k,
                min_k: lo,
                max_k: hi,
            });
        }
        let (a, b) = match self.table.len() {
            1 => (self.table[0], self.table[0]),
            _ => {
                let upper = self
                    .table
                    .partition_point(|r| r.temperature_k < temperature_k)
                    .max(1);
                (self.table[upper - 1], self.table[upper])
            }
        };
        let span = b.temperature_k - a.temperature_k;
        let w = if span > 0.0 {
            (temperature_k - a.temperature_k) / span
        } else {
            0.0
        };
        let mix = |x: f64, y: f64| x + (y - x) * w;
        Ok(MaterialProperties {
            temperature_k,
            youngs_modulus_pa: mix(a.youngs_modulus_pa, b.youngs_modulus_pa),
            thermal_expansion_per_k: mix(a.thermal_expansion_per_k, b.thermal_expansion_per_k),
            conductivity_w_m_k: mix(a.conductivity_w_m_k, b.conductivity_w_m_k),
            specific_heat_j_kg_k: mix(a.specific_heat_j_kg_k, b.specific_heat_j_kg_k),
        })
    }

    /// Young's modulus at T, Pa.
    pub fn youngs_modulus_pa(&self, temperature_k: f64) -> Result<f64, MaterialError> {
        self.at(temperature_k).map(|p| p.youngs_modulus_pa)
    }

    /// Secant thermal expansion coefficient from 293 K to T, 1/K.
    pub fn thermal_expansion_per_k(&self, temperature_k: f64) -> Result<f64, MaterialError> {
        self.at(temperature_k).map(|p| p.thermal_expansion_per_k)
    }

    /// Thermal conductivity at T, W/(m K).
    pub fn conductivity_w_m_k(&self, temperature_k: f64) -> Result<f64, MaterialError> {
        self.at(temperature_k).map(|p| p.conductivity_w_m_k)
    }

    /// Specific heat at T, J/(kg K).
    pub fn specific_heat_j_kg_k(&self, temperature_k: f64) -> Result<f64, MaterialError> {
        self.at(temperature_k).map(|p| p.specific_heat_j_kg_k)
    }

    /// Free thermal strain ε_th = α_sec(T) (T − 293 K) (secant definition), dimensionless.
    pub fn thermal_strain(&self, temperature_k: f64) -> Result<f64, MaterialError> {
        self.at(temperature_k)
            .map(|p| p.thermal_expansion_per_k * (temperature_k - SECANT_REFERENCE_TEMPERATURE_K))
    }

    /// Shear modulus of the isotropic material, G = E / (2 (1 + ν)), Pa.
    pub fn shear_modulus_pa(&self, temperature_k: f64) -> Result<f64, MaterialError> {
        Ok(self.youngs_modulus_pa(temperature_k)? / (2.0 * (1.0 + self.poisson_ratio)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn ti_6al_4v_is_valid_and_interpolates_linearly_between_rows() {
        let ti = Material::ti_6al_4v();
        ti.validate().expect("valid");
        assert_eq!(ti.temperature_range_k(), (293.0, 923.0));
        // Rows are returned exactly.
        assert_relative_eq!(
            ti.youngs_modulus_pa(573.0).unwrap(),
            91.36e9,
            max_relative = 1e-12
        );
        // Midway between 473 K and 573 K.
        let p = ti.at(523.0).unwrap();
        assert_relative_eq!(
            p.youngs_modulus_pa,
            0.5 * (96.34e9 + 91.36e9),
            max_relative = 1e-12
        );
        assert_relative_eq!(
            p.conductivity_w_m_k,
            0.5 * (8.80 + 10.22),
            max_relative = 1e-12
        );
        assert_relative_eq!(
            p.specific_heat_j_kg_k,
            0.5 * (585.3 + 607.2),
            max_relative = 1e-12
        );
        assert_relative_eq!(
            p.thermal_expansion_per_k,
            0.5 * (8.879e-6 + 9.158e-6),
            max_relative = 1e-12
        );
        assert_eq!(ti.thermal_strain(293.0).unwrap(), 0.0);
    }

    /// Fukuhara & Sanpei (1993) measured points (296.3 K: 103.34 GPa, 501.2 K: 95.24 GPa,
    /// 706.5 K: 85.03 GPa, 906.0 K: 75.06 GPa) within the fit's largest residual, 2.1 GPa;
    /// Polev et al. (1985) conductivities (572.18 K: 10.21, 773.16 K: 12.64 W/(m K)) within
    /// 0.02 W/(m K); datasheet secant expansion 9.2e-6/K at 315 °C (588 K) exactly.
    #[test]
    fn ti_6al_4v_table_reproduces_its_sources() {
        let ti = Material::ti_6al_4v();
        for (t, e_gpa) in [
            (296.3, 103.342),
            (501.17, 95.238),
            (706.47, 85.027),
            (906.04, 75.064),
        ] {
            let e = ti.youngs_modulus_pa(t).unwrap() / 1e9;
            assert!(
                (e - e_gpa).abs() < 2.1,
                "E({t} K) = {e} GPa vs measured {e_gpa}"
            );
        }
        for (t, k) in [(572.18, 10.2073), (773.16, 12.6389), (472.93, 8.7991)] {
            let got = ti.conductivity_w_m_k(t).unwrap();
            assert!((got - k).abs() < 0.02, "k({t} K) = {got} vs {k}");
        }
        assert_relative_eq!(
            ti.thermal_expansion_per_k(588.0).unwrap(),
            9.2e-6,
            max_relative = 2e-3
        );
        // Heat capacity at room temperature: measured 546 J/(kg K) at 295 K (Richardson et al.).
        assert!((ti.specific_heat_j_kg_k(295.11).unwrap() - 546.07).abs() < 10.0);
        // MMPDS room-temperature modulus 16.0 Msi = 110.3 GPa (static, tension): the dynamic
        // fit is within 5 %.
        assert!((ti.youngs_modulus_pa(294.0).unwrap() / 110.3e9 - 1.0).abs() < 0.05);
    }

    #[test]
    fn temperatures_outside_the_table_name_the_range() {
        let ti = Material::ti_6al_4v();
        let err = ti.youngs_modulus_pa(1500.0).unwrap_err().to_string();
        assert!(
            err.contains("1500") && err.contains("293") && err.contains("923"),
            "{err}"
        );
        assert!(ti.at(f64::NAN).is_err());
        assert!(ti.at(200.0).is_err());
        let model = ti
            .at(1000.0)
            .unwrap_err()
            .into_model_error("ritz-plate")
            .to_string();
        assert!(
            model.contains("ritz-plate") && model.contains("923"),
            "{model}"
        );
    }

    #[test]
    fn non_physical_values_are_errors_naming_the_quantity() {
        let mut m = Material::ti_6al_4v();
        m.poisson_ratio = 0.5;
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("poisson_ratio")
        );
        let mut m = Material::ti_6al_4v();
        m.table[3].youngs_modulus_pa = -1.0;
        assert!(
            m.validate()
                .unwrap_err()
                .to_string()
                .contains("table[3].youngs_modulus_pa")
        );
        let mut m = Material::ti_6al_4v();
        m.table[2].temperature_k = 300.0;
        assert!(m.validate().unwrap_err().to_string().contains("increase"));
        let mut m = Material::ti_6al_4v();
        m.melting_point_k = 800.0;
        assert!(m.validate().unwrap_err().to_string().contains("melting"));
        assert!(
            Material::by_name("unobtainium")
                .unwrap_err()
                .to_string()
                .contains("ti-6al-4v")
        );
    }

    #[test]
    fn settings_take_a_name_or_a_table() {
        #[derive(Deserialize)]
        struct S {
            material: MaterialSetting,
        }
        let s: S = toml::from_str("material = \"Ti-6Al-4V\"").unwrap();
        assert_eq!(s.material.resolve().unwrap(), Material::ti_6al_4v());
        let text = r#"
            [material]
            name = "steel"
            density_kg_m3 = 7850.0
            poisson_ratio = 0.3
            melting_point_k = 1700.0
            table = [
              { temperature_k = 250.0, youngs_modulus_pa = 200e9, thermal_expansion_per_k = 12e-6, conductivity_w_m_k = 50.0, specific_heat_j_kg_k = 460.0 },
              { temperature_k = 800.0, youngs_modulus_pa = 170e9, thermal_expansion_per_k = 14e-6, conductivity_w_m_k = 40.0, specific_heat_j_kg_k = 600.0 },
            ]
        "#;
        let s: S = toml::from_str(text).unwrap();
        let steel = s.material.resolve().unwrap();
        assert_relative_eq!(
            steel.youngs_modulus_pa(525.0).unwrap(),
            185e9,
            max_relative = 1e-12
        );
        let c = Material::constant("c", 1.0, 0.3, 1e9, 1e-5, 1.0, 1.0, (1.0, 1000.0)).unwrap();
        assert_eq!(c.youngs_modulus_pa(500.0).unwrap(), 1e9);
    }
}
