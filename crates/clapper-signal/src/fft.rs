//! Real FFT plans, made once per length and thread.
//!
//! Planning a length computes its twiddle factors (a sine and cosine
//! each); a function that plans afresh on every call (one cross-correlation
//! per strike) spent a third of `--self-calibrate`'s time in those sines.
//! A plan is the same algorithm whichever thread makes it, so results do
//! not depend on the thread count.

use realfft::num_complex::Complex;
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

/// A reference's spectrum kept from the last cross-correlation against it,
/// with the transform's buffers: a bell's strikes are each lined up on the
/// same average, and transforming it afresh for each was a third of the
/// transforms.
struct Kept {
    /// The transform's length.
    n: usize,
    /// The reference as transformed (its samples, compared in full: a
    /// kept spectrum is used only for the same numbers).
    reference: Vec<f64>,
    /// Its spectrum.
    spectrum: Vec<Complex<f64>>,
    input: Vec<f64>,
    output: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
    out: Vec<f64>,
}

thread_local! {
    static KEPT: RefCell<Option<Kept>> = const { RefCell::new(None) };
}

/// The cross-correlation of `x` against `reference`, zero-padded to
/// `n` samples: `f(out)`
/// sees out[d] = Σ_k reference[k]·x[k + d] (circular, at length `n`: exact,
/// x taken as zero past its end, for d up to `n` less the reference's length).
/// The reference's spectrum is kept for the next call with the same
/// reference and length; the numbers are those of transforming it afresh.
pub(crate) fn correlate<R>(x: &[f64], reference: &[f64], n: usize, f: impl FnOnce(&[f64]) -> R) -> R {
    let (fwd, inv) = plans(n);
    KEPT.with(|k| {
        let mut k = k.borrow_mut();
        let kept = k.take().filter(|c| c.n == n && c.reference == reference);
        let mut c = kept.unwrap_or_else(|| {
            let mut input = fwd.make_input_vec();
            input[..reference.len()].copy_from_slice(reference);
            let mut spectrum = fwd.make_output_vec();
            // The lengths are the plan's own: the transforms cannot fail.
            let _ = fwd.process(&mut input, &mut spectrum);
            let scratch_len = fwd.get_scratch_len().max(inv.get_scratch_len());
            Kept {
                n,
                reference: reference.to_vec(),
                spectrum,
                input,
                output: fwd.make_output_vec(),
                scratch: vec![Complex::new(0.0, 0.0); scratch_len],
                out: inv.make_output_vec(),
            }
        });
        c.input.fill(0.0);
        c.input[..x.len()].copy_from_slice(x);
        let _ = fwd.process_with_scratch(&mut c.input, &mut c.output, &mut c.scratch);
        for (p, q) in c.output.iter_mut().zip(&c.spectrum) {
            *p *= q.conj();
        }
        c.output[0].im = 0.0;
        if let Some(l) = c.output.last_mut() {
            l.im = 0.0;
        }
        let _ = inv.process_with_scratch(&mut c.output, &mut c.out, &mut c.scratch);
        let r = f(&c.out);
        *k = Some(c);
        r
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

    /// The cross-correlation as `self_calibrate::best_lag` made it before
    /// the reference's spectrum was kept.
    fn correlate_afresh(x: &[f64], reference: &[f64], n: usize) -> Vec<f64> {
        let (fwd, inv) = plans(n);
        let mut a = fwd.make_input_vec();
        a[..x.len()].copy_from_slice(x);
        let mut b = fwd.make_input_vec();
        b[..reference.len()].copy_from_slice(reference);
        let (mut sa, mut sb) = (fwd.make_output_vec(), fwd.make_output_vec());
        fwd.process(&mut a, &mut sa).unwrap();
        fwd.process(&mut b, &mut sb).unwrap();
        for (p, q) in sa.iter_mut().zip(&sb) {
            *p *= q.conj();
        }
        sa[0].im = 0.0;
        if let Some(l) = sa.last_mut() {
            l.im = 0.0;
        }
        let mut out = inv.make_output_vec();
        inv.process(&mut sa, &mut out).unwrap();
        out
    }

    #[test]
    fn a_kept_reference_correlates_as_one_transformed_afresh() {
        let wave = |seed: usize, len: usize| -> Vec<f64> {
            (0..len)
                .map(|i| (((i + seed) * 7919) % 1009) as f64 / 504.5 - 1.0)
                .collect()
        };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let (r1, r2) = (wave(1, 300), wave(2, 300));
        // The same reference again, another of the same length, a shorter
        // x than before (the buffer's rest is zero again), another length.
        for (x, r, n) in [
            (wave(3, 500), &r1, 1024),
            (wave(4, 700), &r1, 1024),
            (wave(5, 200), &r1, 1024),
            (wave(6, 500), &r2, 1024),
            (wave(7, 500), &r2, 2048),
            (wave(8, 400), &r1, 1024),
        ] {
            let kept = correlate(&x, r, n, |o| bits(o));
            assert_eq!(kept, bits(&correlate_afresh(&x, r, n)));
        }
    }
}
