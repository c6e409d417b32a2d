//! Gauss-Legendre quadrature nodes and weights on `[0, 1]`.

use std::sync::OnceLock;

use homospline_geom::Real;

/// The rules computed so far, by node count.
static RULES: [OnceLock<(Vec<Real>, Vec<Real>)>; 64] = [const { OnceLock::new() }; 64];

/// [`gauss_legendre`], computed once per node count and kept: the cost asks for its rule at
/// every evaluation.
pub fn gauss_legendre_cached(n: usize) -> &'static (Vec<Real>, Vec<Real>) {
    let n = n.clamp(1, 64);
    RULES[n - 1].get_or_init(|| gauss_legendre(n))
}

/// Gauss-Legendre rule with `n` nodes on `[0, 1]` (`1 <= n <= 64`): exact for polynomials of
/// degree `2n - 1`. Nodes by Newton's method on the Legendre polynomial; ascending.
pub fn gauss_legendre(n: usize) -> (Vec<Real>, Vec<Real>) {
    let n = n.clamp(1, 64);
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        // Initial guess (Tricomi), then Newton on P_n.
        let mut z = (std::f64::consts::PI * (i as Real + 0.75) / (n as Real + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as Real * z * p1 - (k - 1) as Real * p0) / k as Real;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 1 { z } else { p1 };
            let pn1 = if n == 1 { 1.0 } else { p0 };
            dp = n as Real * (z * pn - pn1) / (z * z - 1.0);
            let dz = pn / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        if n == 1 {
            z = 0.0;
            dp = 1.0;
        }
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        // Map [-1, 1] -> [0, 1]; z is the i-th largest root.
        x[n - 1 - i] = 0.5 * (1.0 + z);
        x[i] = 0.5 * (1.0 - z);
        w[n - 1 - i] = 0.5 * wi;
        w[i] = 0.5 * wi;
    }
    (x, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly() {
        for n in 1..=12 {
            let (x, w) = gauss_legendre(n);
            for deg in 0..(2 * n) {
                let q: Real = x.iter().zip(&w).map(|(x, w)| w * x.powi(deg as i32)).sum();
                assert!(
                    (q - 1.0 / (deg as Real + 1.0)).abs() < 1e-13,
                    "n {n} deg {deg}: {q}"
                );
            }
        }
    }
}
