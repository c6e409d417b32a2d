//! The names front ends use for the cost's choices: `FromStr` (and `Display`
//! where the type's own module lacks it) for [`RoughnessForm`], [`ClearanceSearch`] and the
//! presets ([`Preset`]), one spelling each.

use std::fmt;
use std::str::FromStr;

use crate::cost::{ClearanceSearch, CostConfig};
use crate::roughness::RoughnessForm;

/// A closed set of named values that front ends list and read: the command line builds an
/// option's values and their help from it, so a new value is added in one place.
///
/// # Examples
///
/// ```
/// use homospline_spline::{Choice, Preset};
///
/// let names: Vec<&str> = Preset::ALL.iter().map(|p| p.name()).collect();
/// assert_eq!(names, ["paper-voronoi", "paper-original"]);
/// assert_eq!(Preset::choose("original"), Some(Preset::PaperOriginal));
/// ```
pub trait Choice: Copy + Sized + 'static {
    /// Every value, in the order of the option's help.
    const ALL: &'static [Self];
    /// Its name.
    fn name(self) -> &'static str;
    /// One line of help.
    fn help(self) -> &'static str;
    /// Other names it is read by.
    fn aliases(self) -> &'static [&'static str] {
        &[]
    }
    /// The value called `name` (or by one of its aliases).
    fn choose(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|c| c.name() == name || c.aliases().contains(&name))
    }
}

impl Choice for Preset {
    const ALL: &'static [Self] = &Preset::ALL;
    fn name(self) -> &'static str {
        Preset::name(self)
    }
    fn help(self) -> &'static str {
        match self {
            Self::PaperVoronoi => "Cost (10): the original cost and the safety term",
            Self::PaperOriginal => "Cost (9): the original planner's cost",
        }
    }
    fn aliases(self) -> &'static [&'static str] {
        match self {
            Self::PaperVoronoi => &["voronoi", "paper"],
            Self::PaperOriginal => &["original"],
        }
    }
}

impl Choice for RoughnessForm {
    const ALL: &'static [Self] = &RoughnessForm::ALL;
    fn name(self) -> &'static str {
        RoughnessForm::name(self)
    }
    fn help(self) -> &'static str {
        match self {
            Self::Paper => "integral |q''| dt: the paper's (4)",
            Self::Energy => "integral |q''|^2 dt: the bending energy",
            Self::Authors => "sqrt(integral |q''|^2 dt): the authors' code",
        }
    }
}

impl Choice for ClearanceSearch {
    const ALL: &'static [Self] = &ClearanceSearch::ALL;
    fn name(self) -> &'static str {
        ClearanceSearch::name(self)
    }
    fn help(self) -> &'static str {
        match self {
            Self::WorstNode => {
                "Around the worst node only: a class whose curve ends below its target there \
                 and could rank first runs one more round with every-stretch"
            }
            Self::EveryStretch => {
                "Between every two nodes, in every evaluation (1.6 times an evaluation's cost)"
            }
        }
    }
}

/// A name that is none of a choice's names.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} '{given}' (expected {expected})")]
pub struct UnknownName {
    /// What was named: "preset", "roughness form", ...
    pub what: &'static str,
    /// The name given.
    pub given: String,
    /// The names known, for the message: "paper, energy or authors".
    pub expected: &'static str,
}

impl UnknownName {
    /// `given` is not a `what`; `expected` lists the names.
    pub fn new(what: &'static str, given: &str, expected: &'static str) -> Self {
        Self {
            what,
            given: given.to_owned(),
            expected,
        }
    }
}

/// The paper's cost presets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Preset {
    /// Cost (10): the original cost plus the safety term (the default).
    #[default]
    PaperVoronoi,
    /// Cost (9): the original planner's cost, no safety term.
    PaperOriginal,
}

impl Preset {
    /// Both, in the order of the option's help.
    pub const ALL: [Self; 2] = [Self::PaperVoronoi, Self::PaperOriginal];

    /// `paper-voronoi` or `paper-original`.
    pub fn name(self) -> &'static str {
        match self {
            Self::PaperVoronoi => "paper-voronoi",
            Self::PaperOriginal => "paper-original",
        }
    }

    /// The preset's cost.
    pub fn config(self) -> CostConfig {
        match self {
            Self::PaperVoronoi => CostConfig::paper_voronoi(),
            Self::PaperOriginal => CostConfig::paper_original(),
        }
    }
}

impl FromStr for Preset {
    type Err = UnknownName;

    /// The names of [`CostConfig::preset`], short forms included.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "paper-voronoi" | "voronoi" | "paper" => Ok(Self::PaperVoronoi),
            "paper-original" | "original" => Ok(Self::PaperOriginal),
            other => Err(UnknownName::new(
                "preset",
                other,
                "paper-voronoi or paper-original",
            )),
        }
    }
}

impl fmt::Display for Preset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for RoughnessForm {
    type Err = UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s.trim())
            .ok_or_else(|| UnknownName::new("roughness form", s.trim(), "paper, energy or authors"))
    }
}

impl FromStr for ClearanceSearch {
    type Err = UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s.trim()).ok_or_else(|| {
            UnknownName::new("clearance search", s.trim(), "worst-node or every-stretch")
        })
    }
}

impl fmt::Display for ClearanceSearch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_reads_back() {
        for p in Preset::ALL {
            assert_eq!(p.to_string().parse::<Preset>(), Ok(p));
            assert_eq!(Some(p.config()), CostConfig::preset(p.name()));
        }
        for r in RoughnessForm::ALL {
            assert_eq!(r.to_string().parse::<RoughnessForm>(), Ok(r));
        }
        for c in ClearanceSearch::ALL {
            assert_eq!(c.to_string().parse::<ClearanceSearch>(), Ok(c));
        }
        assert_eq!(
            "smooth".parse::<RoughnessForm>().unwrap_err().to_string(),
            "unknown roughness form 'smooth' (expected paper, energy or authors)"
        );
        assert!("".parse::<Preset>().is_err());
    }
}

#[cfg(test)]
mod choice_tests {
    use super::*;

    /// Every value's name and alias reads back to it through `FromStr`, as through
    /// `Choice::choose`: the front ends' two ways of reading a name agree.
    fn reads_back<T: Choice + FromStr + PartialEq + fmt::Debug>() {
        for &c in T::ALL {
            for name in std::iter::once(c.name()).chain(c.aliases().iter().copied()) {
                assert_eq!(name.parse::<T>().ok(), Some(c), "{name}");
                assert_eq!(T::choose(name), Some(c), "{name}");
            }
            assert!(!c.help().is_empty());
        }
        assert_eq!(T::choose("nonesuch"), None);
    }

    #[test]
    fn every_choice_reads_back_by_name_and_alias() {
        reads_back::<Preset>();
        reads_back::<RoughnessForm>();
        reads_back::<ClearanceSearch>();
    }
}
