// Gauss–Legendre quadrature, the one rule every integral in f64 uses (the
// DFG integral, the GGX lobe's normaliser).

/// Gauss–Legendre nodes and weights on [0, 1].
#[derive(Clone, Debug)]
pub(crate) struct Gauss {
    /// The nodes, ascending, in (0, 1).
    pub(crate) nodes: Vec<f64>,
    /// Their weights, summing to 1.
    pub(crate) weights: Vec<f64>,
}

impl Gauss {
    /// The `n`-point rule: Newton's method on the Legendre polynomial from
    /// Tricomi's first guess, converged to f64 rounding.
    pub(crate) fn new(n: usize) -> Gauss {
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for i in 0..n {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                let dx = p / d;
                x -= dx;
                if dx.is_nan() || dx.abs() <= 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            // On [−1, 1], w = 2 / ((1 − x²) P'_n(x)²); halved on [0, 1].
            nodes[n - 1 - i] = 0.5 * (x + 1.0);
            weights[n - 1 - i] = 1.0 / ((1.0 - x * x) * d * d);
        }
        Gauss { nodes, weights }
    }

    /// The (node, weight) pairs, nodes ascending.
    pub(crate) fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.nodes.iter().copied().zip(self.weights.iter().copied())
    }
}

/// P_n(x) and P'_n(x), by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    if n == 0 {
        return (1.0, 0.0);
    }
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    (p1, n as f64 * (x * p1 - p0) / (x * x - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in [1usize, 4, 8, 16, 32] {
            let g = Gauss::new(n);
            for d in 0..2 * n as i32 {
                let q: f64 = g.iter().map(|(x, w)| w * x.powi(d)).sum();
                let exact = 1.0 / f64::from(d + 1);
                assert!((q - exact).abs() < 1e-14, "n {n}, x^{d}: {q} vs {exact}");
            }
            assert!(g.nodes.windows(2).all(|p| p[0] < p[1]));
            assert!(g.nodes.iter().all(|&x| x > 0.0 && x < 1.0));
        }
    }
}
