//! The parameters an extension acts only with ([`Parameter::needs`]): the check that warns of
//! one that is off, and the paper with one extension and what it needs (the soak's variants).

use super::{Parameter, Params, PARAMETERS};

/// A parameter that is on while one it acts only with is off: it then does nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnmetNeed {
    /// The parameter that is on.
    pub parameter: &'static str,
    /// The one it needs, off.
    pub needs: &'static str,
}

impl std::fmt::Display for UnmetNeed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "parameter `{}` acts only with `{}`, which is off: it does nothing",
            self.parameter, self.needs
        )
    }
}

/// The declaration of parameter `name`.
pub fn parameter(name: &str) -> Option<&'static Parameter> {
    PARAMETERS.iter().find(|p| p.name == name)
}

impl Params {
    /// Every parameter that is on while one it acts only with is off, in declaration order.
    pub fn unmet_needs(&self) -> Vec<UnmetNeed> {
        PARAMETERS
            .iter()
            .filter(|p| self.is_on(p.name))
            .flat_map(|p| {
                p.needs
                    .iter()
                    .filter(|n| !self.is_on(n))
                    .map(|&needs| UnmetNeed {
                        parameter: p.name,
                        needs,
                    })
            })
            .collect()
    }

    /// The paper with parameter `name` at its `extended` value, and every parameter it needs
    /// (and they need) too; `None` for an unknown name.
    pub fn paper_with(name: &str) -> Option<Params> {
        let extended = Params::extended();
        let mut p = Params::paper();
        let mut pending = vec![parameter(name)?];
        while let Some(next) = pending.pop() {
            p.take_from(next.name, &extended);
            pending.extend(next.needs.iter().filter_map(|n| parameter(n)));
        }
        Some(p)
    }

    /// The parameters whose `paper` and `extended` values differ: the extensions and the
    /// options of the paper's rules, in declaration order.
    pub fn extension_parameters() -> impl Iterator<Item = &'static Parameter> {
        let (paper, extended) = (Params::paper(), Params::extended());
        PARAMETERS.iter().filter(move |p| {
            let (mut a, mut b) = (paper.clone(), paper.clone());
            a.take_from(p.name, &paper);
            b.take_from(p.name, &extended);
            a != b
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::model::params::EXTENDED_MEMORY_SNAPSHOTS;

    #[test]
    fn a_flag_whose_prerequisite_is_off_is_named_and_the_presets_have_none() {
        assert!(Params::paper().unmet_needs().is_empty());
        assert!(Params::extended().unmet_needs().is_empty());
        let p = Params {
            settled_walls: true,
            round_reflectors: true,
            ..Params::paper()
        };
        assert_eq!(
            p.unmet_needs(),
            vec![
                UnmetNeed {
                    parameter: "round_reflectors",
                    needs: "corner_diagonals"
                },
                UnmetNeed {
                    parameter: "settled_walls",
                    needs: "confirm_segments"
                },
            ]
        );
    }

    #[test]
    fn the_paper_with_one_extension_brings_what_it_needs_and_nothing_else() {
        let p = Params::paper_with("round_reflectors").unwrap();
        let expected = Params {
            round_reflectors: true,
            corner_diagonals: true,
            confirm_segments: true,
            ..Params::paper()
        };
        assert_eq!(p, expected);
        assert!(p.unmet_needs().is_empty());
        let p = Params::paper_with("memory_joints").unwrap();
        assert_eq!(
            (p.memory_snapshots, p.memory_joints),
            (EXTENDED_MEMORY_SNAPSHOTS, true)
        );
        assert!(Params::paper_with("no_such_parameter").is_none());
    }

    #[test]
    fn every_need_names_a_declared_parameter_that_can_be_on() {
        for p in PARAMETERS {
            for n in p.needs {
                let need = parameter(n).unwrap_or_else(|| panic!("{}: {n}", p.name));
                assert!(
                    matches!(
                        need.kind,
                        super::super::ParamKind::Flag | super::super::ParamKind::Count
                    ),
                    "{n} cannot be on"
                );
            }
        }
    }

    #[test]
    fn the_extension_parameters_are_those_the_presets_set_apart() {
        let names: Vec<&str> = Params::extension_parameters().map(|p| p.name).collect();
        assert!(names.contains(&"fit") && names.contains(&"memory_snapshots"));
        assert!(names.contains(&"settled_walls") && names.contains(&"min_piece_points"));
        assert!(!names.contains(&"accuracy_pct") && !names.contains(&"correlate"));
        assert_eq!(names.len(), 30);
    }
}
