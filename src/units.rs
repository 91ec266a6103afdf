//! Length units of files. The engine works in metres; files carry their own unit.

use serde::{Deserialize, Serialize};

/// A length unit a file may use (docs/formats.md §1: `"in"`, `"mm"`, `"cm"`, `"m"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Units {
    /// Inches, the paper's unit.
    #[serde(rename = "in")]
    #[default]
    Inches,
    /// Millimetres.
    #[serde(rename = "mm")]
    Millimetres,
    /// Centimetres.
    #[serde(rename = "cm")]
    Centimetres,
    /// Metres, the engine's internal unit.
    #[serde(rename = "m")]
    Metres,
}

/// Metres in one inch.
pub const METRES_PER_INCH: f64 = 0.0254;

impl Units {
    /// Decimals that show a length to about a millimetre (a tenth of an inch): the inspector's
    /// numbers, where a sonar's tolerance is a few centimetres.
    pub fn fine_decimals(self) -> usize {
        match self {
            Units::Inches | Units::Centimetres => 1,
            Units::Millimetres => 0,
            Units::Metres => 3,
        }
    }

    /// Metres in one of this unit.
    pub fn metres_per_unit(self) -> f64 {
        match self {
            Units::Inches => METRES_PER_INCH,
            Units::Millimetres => 0.001,
            Units::Centimetres => 0.01,
            Units::Metres => 1.0,
        }
    }

    /// Converts a length in this unit to metres.
    pub fn to_m(self, length: f64) -> f64 {
        length * self.metres_per_unit()
    }

    /// Converts a length in metres to this unit.
    pub fn from_m(self, length_m: f64) -> f64 {
        length_m / self.metres_per_unit()
    }

    /// The name used in files and labels.
    pub fn symbol(self) -> &'static str {
        match self {
            Units::Inches => "in",
            Units::Millimetres => "mm",
            Units::Centimetres => "cm",
            Units::Metres => "m",
        }
    }

    /// Parses a unit name as files spell it.
    pub fn parse(name: &str) -> Option<Units> {
        match name {
            "in" => Some(Units::Inches),
            "mm" => Some(Units::Millimetres),
            "cm" => Some(Units::Centimetres),
            "m" => Some(Units::Metres),
            _ => None,
        }
    }
}

/// Inches to metres (the paper's constants are in inches).
pub fn inches(length_in: f64) -> f64 {
    Units::Inches.to_m(length_in)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fine_decimals_resolve_a_tenth_of_an_inch_or_better() {
        for u in [
            Units::Inches,
            Units::Millimetres,
            Units::Centimetres,
            Units::Metres,
        ] {
            let step_m = u.to_m(10f64.powi(-(u.fine_decimals() as i32)));
            assert!(step_m <= inches(0.1) + 1e-12, "{u:?}: {step_m} m");
        }
        // A 2.5 cm sonar tolerance reads 0.025 m, not 0.0 m.
        assert_eq!(
            format!("{:.*}", Units::Metres.fine_decimals(), 0.025),
            "0.025"
        );
    }

    #[test]
    fn conversions_round_trip() {
        for u in [
            Units::Inches,
            Units::Millimetres,
            Units::Centimetres,
            Units::Metres,
        ] {
            assert!((u.from_m(u.to_m(42.0)) - 42.0).abs() < 1e-12);
            assert_eq!(Units::parse(u.symbol()), Some(u));
        }
        assert!((inches(255.0) - 6.477).abs() < 1e-12);
        assert_eq!(Units::parse("ft"), None);
    }
}
