//! The names front ends use for the planner's choices: `FromStr` and `Display` for
//! [`Seed`] and [`Optimizer`], one spelling each.

use std::fmt;
use std::str::FromStr;

use homospline_spline::UnknownName;

use crate::growth::Optimizer;
use crate::planner::Seed;

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
        assert_eq!(
            "bfgs".parse::<Optimizer>().unwrap_err().to_string(),
            "unknown optimizer 'bfgs' (expected nelder-mead or lbfgs)"
        );
    }
}
