//! The planner's options as every front end takes them (the command line, the Python
//! package): names and values checked once, with the messages the user sees.

use homospline_geom::Scene;
use homospline_optim::{GrowthConfig, Optimizer, PlanConfig, Seed};
use homospline_spline::{ClearanceSearch, CostConfig, RoughnessForm};

/// What a front end asks of a plan; `None` keeps the default of the scene or the map.
#[derive(Clone, Debug)]
pub struct PlanOptions {
    /// `voronoi` or `straight`.
    pub seed: String,
    /// Classes to optimise, 1 to 64 (`None`: 5). The straight seed plans one class and
    /// refuses any other count given.
    pub classes: Option<usize>,
    /// `paper-voronoi` or `paper-original`.
    pub preset: String,
    /// Weights and parameters by name, in order.
    pub weights: Vec<(String, f64)>,
    /// `nelder-mead` or `lbfgs`.
    pub optimizer: Option<String>,
    /// `paper`, `energy` or `authors`.
    pub roughness: Option<String>,
    /// `worst-node` or `every-stretch`: where the optimiser's `m(C)` is searched between
    /// quadrature nodes.
    pub clearance_search: Option<String>,
    /// Grid cells per map unit (scenes only).
    pub resolution: Option<f64>,
    /// Worker threads.
    pub threads: Option<usize>,
    /// Most via-points.
    pub max_via: Option<usize>,
    /// Growth rounds.
    pub rounds: Option<usize>,
    /// Hard clearance margin.
    pub clearance_floor: f64,
    /// `dm` as a penalty only: the dm rule off (maps never apply it).
    pub soft_dm: bool,
    /// Classes to leave out.
    pub avoid: Vec<String>,
    /// Limited overlap.
    pub diverse: Option<f64>,
    /// Successive halving of the classes: `off` or a ratio of at least 1 (scenes only).
    pub prune: Option<String>,
    /// Polish rounds for the chosen class, 0 to 10 (scenes only).
    pub polish: usize,
    /// The chosen class's finish: `off` or a work budget in evaluations (scenes only).
    pub finish_within: Option<String>,
    /// Whether a saved graph is given (the Voronoi seed's; the straight seed refuses it).
    pub graph: bool,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            seed: "voronoi".into(),
            classes: None,
            preset: "paper-voronoi".into(),
            weights: Vec::new(),
            optimizer: None,
            roughness: None,
            clearance_search: None,
            resolution: None,
            threads: None,
            max_via: None,
            rounds: None,
            clearance_floor: 0.0,
            soft_dm: false,
            avoid: Vec::new(),
            diverse: None,
            prune: None,
            polish: 0,
            finish_within: None,
            graph: false,
        }
    }
}

/// The planner's configuration for `scene` (its danger and critical points and hazards
/// join the cost), or for a map when `scene` is `None` (the map defaults). The error names
/// the option as the command line spells it.
pub fn plan_config(o: &PlanOptions, scene: Option<&Scene>) -> Result<PlanConfig, String> {
    let mut cost = CostConfig::preset(&o.preset).ok_or_else(|| {
        format!(
            "--preset: unknown preset '{}' (paper-voronoi, paper-original)",
            o.preset
        )
    })?;
    if let Some(s) = scene {
        cost = cost.with_scene_points(s);
    }
    if scene.is_none() {
        // The map defaults of the safety term, whatever the preset; `--weight` may change
        // them below.
        let map = homospline_maps::map_config().growth.cost;
        cost.safety_along = map.safety_along;
        cost.dm = map.dm;
        cost.omega = map.omega;
    }
    for (name, v) in &o.weights {
        cost.set(name.trim(), *v)
            .map_err(|e| format!("--weight {name}={v}: {e}"))?;
    }
    if let Some(k) = o.classes
        && !(1..=64).contains(&k)
    {
        return Err(format!("--classes {k}: must be between 1 and 64"));
    }
    if let Some(r) = o.resolution {
        if scene.is_none() {
            return Err("--resolution applies to scenes; a map's grid is its cells".into());
        }
        if !(r.is_finite() && r > 0.0) {
            return Err(format!("--resolution {r}: must be positive"));
        }
    }
    if let Some(n) = o.threads
        && !(1..=homospline_optim::planner::MAX_THREADS).contains(&n)
    {
        return Err(format!(
            "--threads {n}: must be between 1 and {}",
            homospline_optim::planner::MAX_THREADS
        ));
    }
    let base = match scene {
        Some(_) => PlanConfig::default(),
        None => homospline_maps::map_config(),
    };
    if let Some(form) = &o.roughness {
        cost.roughness = RoughnessForm::from_name(form)
            .ok_or_else(|| format!("--roughness {form}: expected paper, energy or authors"))?;
    }
    if let Some(search) = &o.clearance_search {
        cost.clearance_search = ClearanceSearch::from_name(search).ok_or_else(|| {
            format!("--clearance-search {search}: expected worst-node or every-stretch")
        })?;
    }
    if !(o.clearance_floor.is_finite() && o.clearance_floor >= 0.0) {
        return Err(format!(
            "--clearance-floor {}: must be a finite number >= 0",
            o.clearance_floor
        ));
    }
    if let Some(f) = o.diverse
        && !(f.is_finite() && (0.0..=1.0).contains(&f))
    {
        return Err(format!("--diverse {f}: must be a fraction in [0, 1]"));
    }
    let prune = match o.prune.as_deref().map(str::trim) {
        None => base.prune,
        Some("off") => None,
        Some(text) => match text.parse::<f64>() {
            Ok(r) if r.is_finite() && r >= 1.0 => Some(r),
            _ => {
                return Err(format!(
                    "--prune {text}: expected off or a ratio of at least 1"
                ));
            }
        },
    };
    let finish_within = match o.finish_within.as_deref().map(str::trim) {
        None => base.finish_within,
        Some("off") => None,
        Some(text) => match text.parse::<usize>() {
            Ok(n) if scene.is_some() || n == 0 => Some(n),
            Ok(_) => {
                return Err(
                    "--finish-within applies to scenes; a map's classes are optimised while \
                     its search goes on"
                        .into(),
                );
            }
            Err(_) => {
                return Err(format!(
                    "--finish-within {text}: expected off or a number of evaluations"
                ));
            }
        },
    };
    let rounds = o.rounds.unwrap_or(base.growth.max_rounds);
    if !(1..=100).contains(&rounds) {
        return Err(format!("--rounds {rounds}: must be between 1 and 100"));
    }
    let max_via = o.max_via.unwrap_or(base.growth.max_via_points);
    if !(1..=200).contains(&max_via) {
        return Err(format!("--max-via {max_via}: must be between 1 and 200"));
    }
    if o.polish > 10 {
        return Err(format!("--polish {}: must be between 0 and 10", o.polish));
    }
    if o.polish > 0 && scene.is_none() {
        return Err(
            "--polish applies to scenes; a map's classes are optimised while its \
                    search goes on"
                .into(),
        );
    }
    let seed = match o.seed.as_str() {
        "voronoi" => Seed::Voronoi,
        "straight" => Seed::Straight,
        other => return Err(format!("--seed {other}: expected voronoi or straight")),
    };
    if let (Seed::Straight, Some(k @ 2..)) = (seed, o.classes) {
        return Err(format!(
            "--classes {k}: --seed straight plans one class, from the straight line S-T"
        ));
    }
    if seed == Seed::Straight && o.graph {
        return Err(
            "--graph gives the Voronoi seed's classes; --seed straight plans one class \
                    from the straight line"
                .into(),
        );
    }
    let optimizer = match o.optimizer.as_deref() {
        None => base.growth.optimizer,
        Some("nelder-mead") => Optimizer::NelderMead,
        Some("lbfgs") => Optimizer::Lbfgs,
        Some(other) => {
            return Err(format!(
                "--optimizer {other}: expected nelder-mead or lbfgs"
            ));
        }
    };
    Ok(PlanConfig {
        seed,
        classes: o.classes.unwrap_or(base.classes),
        resolution: o.resolution,
        growth: GrowthConfig {
            cost,
            optimizer,
            max_via_points: max_via,
            max_rounds: rounds,
            ..base.growth.clone()
        },
        threads: o.threads,
        clearance_floor: o.clearance_floor,
        dm_rule: base.dm_rule && !o.soft_dm,
        avoid: o.avoid.clone(),
        diverse: o.diverse,
        prune,
        polish: o.polish,
        finish_within,
        ..base
    })
}
