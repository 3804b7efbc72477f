//! What a model is for: its role (aero, heat flux, conduction, structure, propulsion, control)
//! and the family of the design card each role belongs to. The config names models by role and
//! the registry finds them by it; both read this module and neither the other.

use std::fmt;

/// The four model families of the design card.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    Aero,
    Thermal,
    Structure,
    Propulsion,
    Control,
}

/// What a model does; thermal models split into heat flux at the wall and conduction inside.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Role {
    Aero,
    HeatFlux,
    Conduction,
    Structure,
    Propulsion,
    /// A controller (`hsv_core::control::Controller`): measured outputs in, commands out.
    Control,
}

impl Role {
    pub fn family(self) -> Family {
        match self {
            Role::Aero => Family::Aero,
            Role::HeatFlux | Role::Conduction => Family::Thermal,
            Role::Structure => Family::Structure,
            Role::Propulsion => Family::Propulsion,
            Role::Control => Family::Control,
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Role::Aero => "aero",
            Role::HeatFlux => "heat-flux",
            Role::Conduction => "conduction",
            Role::Structure => "structure",
            Role::Propulsion => "propulsion",
            Role::Control => "control",
        }
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl fmt::Display for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Family::Aero => "aero",
            Family::Thermal => "thermal",
            Family::Structure => "structure",
            Family::Propulsion => "propulsion",
            Family::Control => "control",
        })
    }
}
