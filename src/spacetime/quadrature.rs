//! Gauss–Legendre quadrature of any order: the objective ∫Σwτ² dt of a
//! transition is a smooth integrand over a short interval, so K Gauss points
//! integrate it far better than K uniform samples (exact for degree 2K−1).

/// Nodes and weights of the K-point Gauss–Legendre rule on [-1, 1].
#[derive(Clone, Debug)]
pub struct GaussLegendre {
    pub nodes: Vec<f64>,
    pub weights: Vec<f64>,
}

/// Error when the order is 0 (there is no 0-point rule).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("quadrature needs at least one sample point (got {0}); use samples: 1 or more")]
pub struct ZeroOrder(pub usize);

impl GaussLegendre {
    /// The K-point rule. Nodes are the roots of P_K found by Newton's method
    /// from Tricomi's asymptotic guess; converged to machine precision for any K
    /// used here (tested up to 200).
    pub fn new(k: usize) -> Result<Self, ZeroOrder> {
        if k == 0 {
            return Err(ZeroOrder(k));
        }
        let n = k as f64;
        let mut nodes = vec![0.0; k];
        let mut weights = vec![0.0; k];
        // Roots are symmetric: compute the upper half and mirror.
        for i in 0..k.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(k, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(k, x);
            if d.is_finite() {
                dp = d;
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = x;
            weights[i] = w;
            nodes[k - 1 - i] = -x;
            weights[k - 1 - i] = w;
        }
        // Ascending order is easier to read in reports and plots.
        nodes.reverse();
        weights.reverse();
        Ok(GaussLegendre { nodes, weights })
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Nodes and weights mapped to [a, b] (weights scaled by (b − a)/2).
    pub fn on(&self, a: f64, b: f64) -> (Vec<f64>, Vec<f64>) {
        let h = 0.5 * (b - a);
        let c = 0.5 * (a + b);
        let t = self.nodes.iter().map(|x| c + h * x).collect();
        let w = self.weights.iter().map(|w| h * w).collect();
        (t, w)
    }

    /// ∫_a^b f(t) dt by this rule.
    pub fn integrate(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let h = 0.5 * (b - a);
        let c = 0.5 * (a + b);
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(|(x, w)| w * f(c + h * x))
            .sum::<f64>()
            * h
    }
}

/// P_k(x) and P_k'(x) by the three-term recurrence.
fn legendre(k: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if k == 0 {
        return (1.0, 0.0);
    }
    for j in 2..=k {
        let j = j as f64;
        let p2 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j;
        p0 = p1;
        p1 = p2;
    }
    let d = k as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_points_is_an_error() {
        assert!(GaussLegendre::new(0).is_err());
    }

    #[test]
    fn exact_on_polynomials_up_to_degree_2k_minus_1() {
        for k in 1..=40 {
            let g = GaussLegendre::new(k).unwrap();
            assert_eq!(g.len(), k);
            for deg in 0..(2 * k) {
                // ∫_{-0.3}^{1.7} t^deg dt
                let (a, b) = (-0.3f64, 1.7f64);
                let exact = (b.powi(deg as i32 + 1) - a.powi(deg as i32 + 1)) / (deg as f64 + 1.0);
                let got = g.integrate(a, b, |t| t.powi(deg as i32));
                let scale = exact.abs().max(1.0);
                assert!(
                    (got - exact).abs() <= 1e-12 * scale * (deg as f64 + 1.0),
                    "k={k} deg={deg} got {got} exact {exact}"
                );
            }
            // and not exact at degree 2k (the rule is not better than claimed);
            // the error falls like 4^-k, so only checkable for small k.
            if k > 10 {
                continue;
            }
            let deg = 2 * k as i32;
            let exact = 2.0 / (deg as f64 + 1.0);
            let got = g.integrate(-1.0, 1.0, |t| t.powi(deg));
            assert!((got - exact).abs() > 1e-14, "k={k}");
        }
    }

    #[test]
    fn high_order_nodes_are_sorted_inside_and_weights_sum_to_two() {
        for k in [1, 2, 7, 80, 200] {
            let g = GaussLegendre::new(k).unwrap();
            assert!(g.nodes.windows(2).all(|w| w[0] < w[1]));
            assert!(g.nodes.iter().all(|x| x.abs() < 1.0));
            let s: f64 = g.weights.iter().sum();
            assert!((s - 2.0).abs() < 1e-12, "k={k} sum {s}");
            assert!(g.weights.iter().all(|w| *w > 0.0 && w.is_finite()));
        }
    }

    #[test]
    fn smooth_integrand_converges() {
        let g = GaussLegendre::new(20).unwrap();
        let got = g.integrate(0.0, std::f64::consts::PI, f64::sin);
        assert!((got - 2.0).abs() < 1e-14);
    }
}
