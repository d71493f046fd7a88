//! Real FFT plans, made once per length and thread.
//!
//! Planning a length computes its twiddle factors (a sine and cosine
//! each); a function that plans afresh on every call (one cross-correlation
//! per strike) spent a third of `--self-calibrate`'s time in those sines.
//! A plan is the same algorithm whichever thread makes it, so results do
//! not depend on the thread count.

use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use std::cell::RefCell;
use std::sync::Arc;

thread_local! {
    static PLANNER: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
}

/// The forward and inverse real transforms of length `n` (samples),
/// planned once per thread and length.
pub(crate) fn plans(n: usize) -> (Arc<dyn RealToComplex<f64>>, Arc<dyn ComplexToReal<f64>>) {
    PLANNER.with(|p| {
        let mut p = p.borrow_mut();
        (p.plan_fft_forward(n), p.plan_fft_inverse(n))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cached_plan_transforms_as_a_fresh_one_does() {
        let n = 1000;
        let x: Vec<f64> = (0..n).map(|i| ((i * 37) % 101) as f64 - 50.0).collect();
        let fresh = RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let (a, b) = (plans(n).0, plans(n).0);
        assert!(Arc::ptr_eq(&a, &b), "the second call reuses the plan");
        let run = |f: &Arc<dyn RealToComplex<f64>>| {
            let mut i = x.clone();
            let mut o = f.make_output_vec();
            f.process(&mut i, &mut o).unwrap();
            o
        };
        assert_eq!(run(&fresh), run(&a));
    }
}
