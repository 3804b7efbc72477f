//! Scramjet propulsion: the `scramjet-1d` (fidelity 1) and `scramjet-q1d` (fidelity 2) models,
//! each evaluated on spanwise sections of the deformed body mesh (paper §II.C, §III.E).
//!
//! **What the engine owns.** The inlet ramp (`inlet-ramp`, nose to inlet) and the external
//! nozzle (`nozzle`, engine exit to tail) of the body mesh, both tagged `Propulsion`, and the
//! unmeshed internal flow path between the inlet face (ramp end to cowl lip) and the engine
//! exit. Its loads are the gauge-pressure integrals over the ramp and nozzle plus the momentum
//! balance of the flow path; `panel_pressure_pa` carries its pressures on the ramp and nozzle
//! panels (freestream elsewhere) so the body aero, which integrates `MainBody` panels only,
//! never counts them twice. The cowl underside and side walls stay with the body aero.
//!
//! **Sections.** Each spanwise column of the body mesh's ramp, cowl and nozzle strips gives a
//! two-dimensional section (the panels' edge midpoints in the x-z plane, so bending and
//! torsion change each section's ramp and nozzle angles). The engine is solved at the centres
//! of `spanwise_strips` equal-width bands, on sections interpolated between columns; the
//! sectional force, pitching moment and mass flow per unit span are fitted across the span by
//! quadratic least squares and integrated (paper §III.E); the spanwise first moments of the
//! fitted forces give the rolling and yawing moments. Panel pressures are the fit evaluated at
//! each column. The reported station states are those of the middle section.
//!
//! **Quasi-steady.** The engine sees the flight condition's Mach number, altitude and angle of
//! attack and the deformed geometry; sideslip, body rates and elastic panel velocities are not
//! used (the paper couples MASIV the same way, §II.C).
//!
//! **Sign conventions.** Body axes (x forward, z down), moments about the `[reference]`
//! moment point. Thrust is the body x force, lift is -(body z force).
//!
//! **`scramjet-1d`** (after Bolender & Doman, "Nonlinear longitudinal dynamical model of an
//! air-breathing hypersonic vehicle", J. Spacecraft Rockets 44(2), 2007): one bow shock from
//! the ramp (deflection = ramp angle + α), mass capture with spillage when the shock passes
//! ahead of the cowl lip, the turn into the duct and an isentropic diffuser to the combustor
//! area, a constant-area combustor with Rayleigh heat addition and the fuel's mass,
//! thermal-choking detection, an isentropic internal nozzle and the plume aftbody below.
//!
//! **`scramjet-q1d`** (after the structure of MASIV, paper §III.E, in reduced form): oblique
//! shocks and Prandtl-Meyer expansions panel by panel along the ramp, a cowl shock and its
//! reflections between the duct walls to the isolator exit deciding whether the inlet starts,
//! the same turn into the duct, a quasi-one-dimensional combustor integrated along its length
//! with area change, wall friction and fuel mass and heat released along a mixing-efficiency
//! curve, an isentropic internal nozzle and the plume aftbody below.
//!
//! **Inlet face and duct (both models, [`capture`], [`duct_entry`]).** The face carries the
//! shock-layer flow, or, once the bow shock enters the cowl, shocked flow and freestream side
//! by side; its stream thrust is their sum. The flow enters the duct by stream-thrust
//! averaging on the duct axis (Heiser & Pratt 1994): mass, energy and axial stream thrust
//! kept, the transverse momentum given to the cowl. Issue 10 item 8 found that the former
//! isentropic turn (1-d) and wave-system end state filled isentropically (q1d) made 1.19 and
//! 0.96 kN/m of axial force at Mach 6 from duct walls that have no axial area, and that the
//! face pressure acted along the flow instead of normal to the face.
//!
//! **Aftbody (both models).** The exhaust expands as a quasi-one-dimensional isentropic stream
//! tube between the aftbody and a straight shear layer from the cowl trailing edge, turned
//! down by the angle that matches plume and external pressures (as B&D match their plume to
//! the external flow), not below the external pressure ([`plume_pressures`]). Issue 10 item 8
//! replaced the former aftbodies: q1d's simple wave held the nozzle-corner pressure over the
//! whole aftbody (263 kN instead of 41 kN at φ 0.45, Mach 6, 26 km), and 1-d's Chavez &
//! Schmidt law p_e/(1 + (s/L)(p_e/p∞ − 1)) gives a mean that grows only as ln(p_e/p∞), which
//! turned its thrust down with α against Bolender & Doman's.
//!
//! **Where to trust them.** Validated against conservation laws of Heiser & Pratt's cycle
//! analysis (tests/cycle.rs): from shock-on-lip up the engine force is the stream-thrust
//! difference S_e − ṁV∞ plus the aftbody force (1e-9), the exit T0 closes the burner energy
//! balance (1e-9), the frictionless duct exerts no axial force (1e-9, q1d 1e-7), and the
//! thrust stays below the fully expanded cycle (1-d 38-51 %, q1d 30-49 % of it at
//! shock-on-lip, φ 0.1-0.6); components against tables and closed forms (validation.rs,
//! plume.rs: θ-β-M, Rayleigh, Fanno, shock-on-lip, choking φ, plume area-Mach). Against the
//! published Bolender & Doman thrust fit (Parker et al., J. Guidance Control Dynamics 30(3),
//! 2007) at Mach 8, 85 kft: ∂T/∂φ 0.70× (1-d) and 0.71× (q1d), ∂T/∂α at φ 0.25 0.73× and
//! 0.64×, ∂²T/∂φ∂α 0.53× and 0.55× (bands: factor 2, 3, 2). On the sample at Mach 6, 26 km,
//! α −4° to 8°, q1d gives 7-10 % less thrust than 1-d at φ 0.3 and 2-3.4 kN less at φ 0.13:
//! its duct wall friction (c_f 0.002, about 3.3 kN); with c_f = 0 the two agree exactly while
//! unchoked. At φ 0.13, α 0 the net thrust (1-d 6.9 kN, q1d 4.5 kN) is a difference of large
//! terms: ramp drag 13.7 kN against 20.6 kN (1-d) and 21.5 kN (q1d) of aftbody thrust; the
//! constant-area duct adds none (impulse conserved), so fuel thrust is aftbody thrust.
//!
//! **Against a published cycle (tests/heiser_pratt.rs).** Set to the idealisation of Heiser &
//! Pratt's stream-thrust analysis (Hypersonic Airbreathing Propulsion, 1994, ch. 4: one
//! perfect gas, no burner friction, fuel without axial momentum, isentropic diffuser and
//! internal nozzle, exhaust fully expanded) at their reference M0 = 10, T0 ≈ 222 K,
//! ψ = T3/T0 = 7, through settings and a section geometry only, both engines reproduce the
//! published cycle's station values (T3, V3, p3, T4, V4, p4, T10, V10), specific thrust and
//! specific impulse: with a constant-area burner `scramjet-1d` to 1e-6 and `scramjet-q1d`
//! (`combustor_area_ratio` 1, c_f 0) to 1e-5, for an isentropic inlet (φ 0.5: F/ṁ0 455 N s/kg,
//! I_sp 3189 s) and for Bolender & Doman's 6.2° ramp shock with the lip on it (η_c 0.989;
//! φ 0.5: 427 N s/kg, 2990 s); with Heiser & Pratt's constant-pressure burner (A4/A3 from
//! their relations, heat released linearly) `scramjet-q1d` within 0.24 % on T4, 0.42 % on p4
//! and 0.03 % on F/ṁ0 and I_sp at φ 1 (847 N s/kg, 2968 s; bands 1 %, 2 %, 1 %). So the cycle
//! arithmetic (capture, duct entry, diffuser, burner with fuel mass, nozzle, force accounting)
//! is that of the published analysis; what it does not show is the sample engine's own
//! losses: its mixed-out duct entry, shock inlet at Mach 6 and under-expanded plume.
//!
//! Use them for thrust, lift and moment of a started, unchoked, under-expanded engine and
//! their trends in φ and α, to about a factor 1.5 in absolute thrust against Bolender &
//! Doman. Not trustworthy: absolute thrust of the sample engine against a real engine
//! (Heiser & Pratt's printed reference-case figures, with η_c = η_e = 0.9, burner friction,
//! fuel momentum and γ 1.36/1.24, are outside what one-γ, loss-free components can be set
//! to; the sample's inlet barely compresses, combustor entry about Mach 4.9 and 314 K at
//! Mach 6, where hydrogen would not ignite and no model checks ignition), thermal choking (φ ≳ 0.43 at Mach 6, 26 km: sonic exit at the limiting heat, a
//! real engine would unstart) and unstart (crude loads), over-expanded exhausts, the aftbody
//! pressure distribution (1-D plume with a straight shear layer, not a method-of-characteristics
//! solution), and the duct-entry losses (stream-thrust averaging is the fully mixed state:
//! total pressure 19 % below the ramp flow's at Mach 6, more than a cowl shock alone costs).
//!
//! **Off-design.** Spillage, thermal choking and unstart are statuses, never NaN. At thermal
//! choking the combustor takes the largest heat release it can pass (sonic exit) and reports
//! `thermal-choking` (a real engine would unstart). An unstarted section (bow shock detached,
//! or the inlet or diffuser cannot pass the flow) captures nothing: its ramp keeps its
//! external pressure (when the bow shock detaches, each ramp segment gets the
//! modified-Newtonian pressure matched to the weak shock at θ_max, continuous in the turning
//! angle up to the pitot pressure at 90°, as in the shock-expansion aero model) and its nozzle
//! the freestream pressure. Negative or non-finite φ, subsonic flight and a mesh without the
//! engine surfaces are errors.

mod flow;
mod geometry;
mod inlet;
mod model;
mod one_d;
mod quasi_one_d;
mod section;
mod settings;
mod span;

use hsv_core::error::ModelError;
use hsv_core::geometry::GeometryConfig;
use hsv_core::propulsion::PropulsionModel;
use hsv_core::registry::{Constructor, ModelContext, ModelDescriptor};
use nalgebra::Point3;

pub use flow::{
    CombustorExit, Compression, FlowState, Turned, burned_total_temperature_k,
    constant_area_combustor, supersonic_area_change, turn,
};
pub use geometry::{EngineSurfaces, SectionGeometry, direction, slope_rad};
pub use inlet::{Capture, capture, duct_entry, stream_thrust_average};
pub use model::{Scramjet, SectionEngine};
pub use one_d::{OneDEngine, aftbody_mean_pressure_pa, aftbody_pressure_pa};
pub use quasi_one_d::{Burner, QuasiOneDEngine, mixing_efficiency};
pub use section::{
    COMBUSTOR_ENTRY, COMBUSTOR_EXIT, Fuel, INLET, NOZZLE_EXIT, SectionConditions, SectionSolution,
    Station, plume_pressures, shear_layer_angle_rad,
};
pub use settings::{
    Checker, HYDROGEN_HEATING_VALUE_J_KG, HYDROGEN_STOICHIOMETRIC_FUEL_AIR_RATIO, OneDSettings,
    QuasiOneDSettings,
};
pub use span::SpanFit;

/// Registered name of `scramjet-1d`.
pub const SCRAMJET_1D: &str = one_d::NAME;
/// Registered name of `scramjet-q1d`.
pub const SCRAMJET_Q1D: &str = quasi_one_d::NAME;

/// `scramjet-1d` on spanwise sections.
pub type Scramjet1d = Scramjet<OneDEngine>;
/// `scramjet-q1d` on spanwise sections.
pub type ScramjetQ1d = Scramjet<QuasiOneDEngine>;

impl SectionEngine for OneDEngine {
    fn name(&self) -> &'static str {
        one_d::NAME
    }

    fn solve(
        &self,
        geometry: &SectionGeometry,
        conditions: &SectionConditions<'_>,
        out: &mut SectionSolution,
    ) -> Result<(), ModelError> {
        OneDEngine::solve(self, geometry, conditions, out)
    }
}

impl SectionEngine for QuasiOneDEngine {
    fn name(&self) -> &'static str {
        quasi_one_d::NAME
    }

    fn solve(
        &self,
        geometry: &SectionGeometry,
        conditions: &SectionConditions<'_>,
        out: &mut SectionSolution,
    ) -> Result<(), ModelError> {
        QuasiOneDEngine::solve(self, geometry, conditions, out)
    }
}

impl OneDSettings {
    /// The engine these settings describe for `geometry`; errors name `<key_path>.<key>`.
    pub fn engine(
        &self,
        geometry: &GeometryConfig,
        check: &Checker<'_>,
    ) -> Result<(OneDEngine, usize), ModelError> {
        let strips = check.count("spanwise_strips", self.spanwise_strips, 3, 101)?;
        let fuel = settings::fuel(
            check,
            self.stoichiometric_fuel_air_ratio,
            self.fuel_heating_value_j_kg,
            self.combustion_efficiency,
        )?;
        let (diffuser, nozzle) = settings::area_ratios(
            check,
            geometry,
            self.diffuser_area_ratio,
            self.internal_nozzle_area_ratio,
            1.0,
        )?;
        Ok((
            OneDEngine {
                fuel,
                diffuser_area_ratio: diffuser,
                internal_nozzle_area_ratio: nozzle,
            },
            strips,
        ))
    }
}

impl QuasiOneDSettings {
    /// The engine these settings describe for `geometry`; errors name `<key_path>.<key>`.
    pub fn engine(
        &self,
        geometry: &GeometryConfig,
        check: &Checker<'_>,
    ) -> Result<(QuasiOneDEngine, usize), ModelError> {
        let strips = check.count("spanwise_strips", self.spanwise_strips, 3, 101)?;
        let fuel = settings::fuel(
            check,
            self.stoichiometric_fuel_air_ratio,
            self.fuel_heating_value_j_kg,
            self.combustion_efficiency,
        )?;
        let area_ratio = check.range(
            "combustor_area_ratio",
            self.combustor_area_ratio,
            0.0,
            10.0,
            true,
        )?;
        let (diffuser, nozzle) = settings::area_ratios(
            check,
            geometry,
            self.diffuser_area_ratio,
            self.internal_nozzle_area_ratio,
            area_ratio,
        )?;
        let isolator = check.range(
            "isolator_length_fraction",
            self.isolator_length_fraction,
            0.0,
            1.0,
            true,
        )?;
        let combustor = check.range(
            "combustor_length_fraction",
            self.combustor_length_fraction,
            0.0,
            1.0,
            true,
        )?;
        if isolator + combustor >= 1.0 {
            return Err(check.fail(
                "combustor_length_fraction",
                format!(
                    "isolator_length_fraction + combustor_length_fraction = {} leaves no internal nozzle; keep the sum below 1",
                    isolator + combustor
                ),
            ));
        }
        Ok((
            QuasiOneDEngine {
                fuel,
                diffuser_area_ratio: diffuser,
                internal_nozzle_area_ratio: nozzle,
                combustor_area_ratio: area_ratio,
                wall_friction_coefficient: check.range(
                    "wall_friction_coefficient",
                    self.wall_friction_coefficient,
                    0.0,
                    0.05,
                    false,
                )?,
                mixing_shape_parameter: check.range(
                    "mixing_shape_parameter",
                    self.mixing_shape_parameter,
                    1.0,
                    100.0,
                    false,
                )?,
                isolator_length_fraction: isolator,
                combustor_length_fraction: combustor,
                combustor_steps: check.count(
                    "combustor_steps",
                    self.combustor_steps,
                    10,
                    100_000,
                )?,
            },
            strips,
        ))
    }
}

/// The body geometry of the region and the vehicle's moment reference point.
fn vehicle_tables(
    ctx: &ModelContext<'_>,
    model: &str,
) -> Result<(GeometryConfig, Point3<f64>), ModelError> {
    let geometry = ctx.region.body_geometry(model)?.clone();
    Ok((geometry, ctx.region.reference.moment_point()))
}

fn build_1d(ctx: &ModelContext<'_>) -> Result<Box<dyn PropulsionModel>, ModelError> {
    let settings: OneDSettings = ctx.parse_settings()?;
    let (geometry, reference) = vehicle_tables(ctx, one_d::NAME)?;
    let check = Checker {
        file: ctx.file,
        key_path: ctx.key_path,
    };
    let (engine, strips) = settings.engine(&geometry, &check)?;
    Ok(Box::new(Scramjet::new(engine, strips, reference)))
}

fn build_q1d(ctx: &ModelContext<'_>) -> Result<Box<dyn PropulsionModel>, ModelError> {
    let settings: QuasiOneDSettings = ctx.parse_settings()?;
    let (geometry, reference) = vehicle_tables(ctx, quasi_one_d::NAME)?;
    let check = Checker {
        file: ctx.file,
        key_path: ctx.key_path,
    };
    let (engine, strips) = settings.engine(&geometry, &check)?;
    Ok(Box::new(Scramjet::new(engine, strips, reference)))
}

hsv_core::register_model!(ModelDescriptor {
    name: one_d::NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 1,
    summary: "1-D scramjet after Bolender & Doman (2007): ramp shock with spillage, \
              momentum-conserving turn into the duct, isentropic diffuser, Rayleigh combustor \
              with choking detection, quasi-1-D plume aftbody bounded by a pressure-matched shear layer; on \
              spanwise strips with a quadratic fit. Trust: started, unchoked engines and their \
              phi/alpha trends (0.5-0.7x Bolender & Doman's published slopes at Mach 8); set to \
              Heiser & Pratt's idealisation it reproduces their constant-area stream-thrust \
              cycle (M0 10, psi 7) to 1e-6; not choked or unstarted engines, not the sample's \
              absolute Isp",
    settings_doc: "spanwise_strips = 5                  # sections across the engine (>= 3)\n\
                   stoichiometric_fuel_air_ratio = 0.0291 # H2 (Heiser & Pratt 1994)\n\
                   fuel_heating_value_j_kg = 1.2e8      # H2 lower heating value (Heiser & Pratt 1994)\n\
                   combustion_efficiency = 0.9          # fraction of the heating value released\n\
                   # diffuser_area_ratio = 1.0          # combustor area / inlet height; default from [geometry]\n\
                   # internal_nozzle_area_ratio = 1.0   # nozzle exit / combustor area (>= 1); default from [geometry]\n\
                   # Trustworthy (tests/cycle.rs, bolender_doman.rs): started, unchoked, under-expanded engines;\n\
                   #   force = Heiser & Pratt stream-thrust difference + aftbody (exact), mass and T0 conserved,\n\
                   #   dT/dphi 0.70x and dT/dalpha 0.73x Bolender & Doman's published fit at Mach 8.\n\
                   # Published cycle (tests/heiser_pratt.rs): set to Heiser & Pratt's stream-thrust idealisation\n\
                   #   (one gas, no friction, isentropic diffuser and nozzle, full expansion) at M0 10, psi 7 it\n\
                   #   reproduces their constant-area cycle to 1e-6: station values, F/m0 and Isp (phi 0.5:\n\
                   #   455 N s/kg, 3189 s; behind B&D's 6.2 deg ramp shock 427 N s/kg, 2990 s).\n\
                   # Not: thermal choking (phi above ~0.43 at Mach 6, 26 km), unstart, over-expanded exhaust,\n\
                   #   the sample engine's absolute Isp (its mixed-out duct entry, Mach 6 inlet and plume losses\n\
                   #   are not validated; combustor entry ~Mach 4.9, 314 K; ignition is not modelled), aftbody\n\
                   #   pressure distribution (1-D plume, not MOC)",
    constructor: Constructor::Propulsion(build_1d),
});

hsv_core::register_model!(ModelDescriptor {
    name: quasi_one_d::NAME,
    origin: env!("CARGO_PKG_NAME"),
    fidelity: 2,
    summary: "Quasi-1-D scramjet: 2-D inlet shocks with cowl-shock reflections (start check), \
              momentum-conserving turn into the duct, combustor integrated with area change, \
              friction and mixing-limited heat release, quasi-1-D plume aftbody bounded by a \
              pressure-matched shear layer; on spanwise strips with a quadratic fit. Trust: \
              started, unchoked engines and their phi/alpha trends (0.5-0.7x Bolender & Doman's \
              published slopes at Mach 8); set to Heiser & Pratt's idealisation it reproduces \
              their constant-area (1e-5) and constant-pressure (0.5 %) stream-thrust cycles; not \
              choked or unstarted engines, not the sample's absolute Isp",
    settings_doc: "spanwise_strips = 5                  # sections across the engine (>= 3)\n\
                   stoichiometric_fuel_air_ratio = 0.0291 # H2 (Heiser & Pratt 1994)\n\
                   fuel_heating_value_j_kg = 1.2e8      # H2 lower heating value (Heiser & Pratt 1994)\n\
                   combustion_efficiency = 0.9          # fraction of the heating value released once mixed\n\
                   combustor_area_ratio = 1.0           # combustor exit / entry area\n\
                   wall_friction_coefficient = 0.002    # c_f in the combustor\n\
                   mixing_shape_parameter = 5.0         # theta of eta_m = theta x / (1 + (theta - 1) x)\n\
                   isolator_length_fraction = 0.2       # inlet face to combustor entry / engine length (cowl waves: start check)\n\
                   combustor_length_fraction = 0.5      # combustor / engine length\n\
                   combustor_steps = 200                # RK4 steps along the combustor\n\
                   # diffuser_area_ratio = 1.0          # combustor entry / inlet height; default from [geometry]\n\
                   # internal_nozzle_area_ratio = 1.0   # nozzle exit / combustor exit (>= 1); default from [geometry]\n\
                   # Trustworthy (tests/cycle.rs, bolender_doman.rs): started, unchoked, under-expanded engines;\n\
                   #   force = Heiser & Pratt stream-thrust difference + aftbody (exact), mass and T0 conserved,\n\
                   #   dT/dphi 0.71x and dT/dalpha 0.64x Bolender & Doman's published fit at Mach 8. Its duct\n\
                   #   wall friction costs ~3.3 kN at Mach 6, 26 km: the whole difference to scramjet-1d there.\n\
                   # Published cycle (tests/heiser_pratt.rs): with c_f = 0 and Heiser & Pratt's idealisation at\n\
                   #   M0 10, psi 7 it reproduces their constant-area cycle (combustor_area_ratio = 1) to 1e-5 and,\n\
                   #   with their A4/A3 and mixing_shape_parameter = 1, their constant-pressure cycle within 0.24 %\n\
                   #   on T4, 0.42 % on p4 and 0.03 % on F/m0 and Isp (phi 1: 847 N s/kg, 2968 s).\n\
                   # Not: thermal choking (phi above ~0.43 at Mach 6, 26 km), unstart, over-expanded exhaust,\n\
                   #   the sample engine's absolute Isp (inlet, duct-entry and plume losses not validated;\n\
                   #   ignition is not modelled), the cowl wave pattern (it only decides start), aftbody\n\
                   #   pressure distribution (1-D plume, not MOC)",
    constructor: Constructor::Propulsion(build_q1d),
});
