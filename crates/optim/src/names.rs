//! The names front ends use for the planner's choices: [`Choice`] (every value with its
//! help, for the command line), `FromStr` and `Display` for [`Seed`] and [`Optimizer`], one
//! spelling each.

use std::fmt;
use std::str::FromStr;

use homospline_spline::{Choice, UnknownName};

use crate::growth::Optimizer;
use crate::planner::Seed;

impl Choice for Seed {
    const ALL: &'static [Self] = &[Self::Voronoi, Self::Straight];
    fn name(self) -> &'static str {
        Seed::name(self)
    }
    fn help(self) -> &'static str {
        match self {
            Self::Voronoi => {
                "One seed per homotopy class of the Voronoi graph (the paper's planner)"
            }
            Self::Straight => "The straight line S-T (the original planner; one class)",
        }
    }
}

impl Choice for Optimizer {
    const ALL: &'static [Self] = &[Self::NelderMead, Self::Lbfgs];
    fn name(self) -> &'static str {
        Optimizer::name(self)
    }
    fn help(self) -> &'static str {
        match self {
            Self::NelderMead => "Nelder-Mead, the paper's method",
            Self::Lbfgs => "L-BFGS on the analytic gradient",
        }
    }
}

impl FromStr for Seed {
    type Err = UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "voronoi" => Ok(Self::Voronoi),
            "straight" => Ok(Self::Straight),
            other => Err(UnknownName::new("seed", other, "voronoi or straight")),
        }
    }
}

impl fmt::Display for Seed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Optimizer {
    /// `nelder-mead` or `lbfgs`.
    pub fn name(self) -> &'static str {
        match self {
            Self::NelderMead => "nelder-mead",
            Self::Lbfgs => "lbfgs",
        }
    }
}

impl FromStr for Optimizer {
    type Err = UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "nelder-mead" => Ok(Self::NelderMead),
            "lbfgs" => Ok(Self::Lbfgs),
            other => Err(UnknownName::new("optimizer", other, "nelder-mead or lbfgs")),
        }
    }
}

impl fmt::Display for Optimizer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_reads_back() {
        for s in [Seed::Voronoi, Seed::Straight] {
            assert_eq!(s.to_string().parse::<Seed>(), Ok(s));
        }
        for o in [Optimizer::NelderMead, Optimizer::Lbfgs] {
            assert_eq!(o.to_string().parse::<Optimizer>(), Ok(o));
        }
        for &s in <Seed as Choice>::ALL {
            assert_eq!(Seed::choose(s.name()), Some(s));
            assert_eq!(s.name().parse::<Seed>(), Ok(s));
        }
        for &o in <Optimizer as Choice>::ALL {
            assert_eq!(Optimizer::choose(o.name()), Some(o));
            assert_eq!(o.name().parse::<Optimizer>(), Ok(o));
        }
        assert_eq!(
            "bfgs".parse::<Optimizer>().unwrap_err().to_string(),
            "unknown optimizer 'bfgs' (expected nelder-mead or lbfgs)"
        );
    }
}
