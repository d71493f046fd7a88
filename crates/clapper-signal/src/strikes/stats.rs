//! Small statistics the strike finder shares: medians and peaks.

/// The median of `v` (the upper of the middle two), found in linear time.
pub(super) fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let k = v.len() / 2;
    Some(*v.select_nth_unstable_by(k, f64::total_cmp).1)
}

pub(super) fn weighted_median(v: &mut [(f64, f64)]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = v.iter().map(|p| p.1).sum();
    let mut acc = 0.0;
    for p in v.iter() {
        acc += p.1;
        if acc >= 0.5 * total {
            return Some(p.0);
        }
    }
    v.last().map(|p| p.0)
}

/// Indices of the local maxima of `v` that are the largest within `sep`
/// either side (ties to the earliest), each more than `sep` after the
/// last, and above 0.
pub(super) fn local_peaks(v: &[f64], sep: usize) -> Vec<usize> {
    if v.iter().any(|x| x.is_nan()) {
        return local_peaks_by_window(v, sep);
    }
    let n = v.len();
    let mut out: Vec<usize> = vec![];
    let mut m = 0;
    // Bounded: `m` grows at every pass. A sample is a peak where none
    // within `sep` after it is larger and none within `sep` before it as
    // large; a sample beaten by a later one within `sep` beats none of
    // those between (so the search goes on from the later), and one that
    // no later sample within `sep` beats leaves none of those a peak.
    while m < n {
        let x = v[m];
        let after_last = out.last().is_none_or(|&p| m > p + sep);
        // (No NaN here: `x <= 0.0` is "not above 0".)
        if x <= 0.0 || !after_last {
            m += 1;
            continue;
        }
        let hi = (m + sep).min(n - 1);
        if let Some(j) = (m + 1..=hi).find(|&j| v[j] > x) {
            m = j;
            continue;
        }
        if v[m.saturating_sub(sep)..m].iter().all(|&y| y < x) {
            out.push(m);
        }
        m = hi + 1;
    }
    out
}

/// [`local_peaks`] by the window's first maximum at every sample (where
/// `v` holds a NaN, and to test the quicker search against).
fn local_peaks_by_window(v: &[f64], sep: usize) -> Vec<usize> {
    let n = v.len();
    let mut out: Vec<usize> = vec![];
    // The window [m − sep, m + sep]'s first maximum, by a deque of indices
    // whose values fall (an earlier equal value stays in front): linear time.
    let mut dq: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
    let mut next = 0;
    for m in 0..n {
        while next < n && next <= m + sep {
            while dq.back().is_some_and(|&b| v[b] < v[next]) {
                dq.pop_back();
            }
            dq.push_back(next);
            next += 1;
        }
        while dq.front().is_some_and(|&f| f + sep < m) {
            dq.pop_front();
        }
        let after_last = out.last().is_none_or(|&p| m > p + sep);
        if dq.front() == Some(&m) && v[m] > 0.0 && after_last {
            out.push(m);
        }
    }
    out
}

/// A strike's typical height in `v`: the 90th percentile of its peaks
/// (a bell strikes about once in every four of them).
pub(super) fn typical_peak(v: &[f64], sep: usize) -> f64 {
    let mut h: Vec<f64> = local_peaks(v, sep).iter().map(|&m| v[m]).collect();
    // The element sorting would put there, by selection (linear time).
    let k = h.len() * 9 / 10;
    if k >= h.len() {
        return 1.0;
    }
    Some(*h.select_nth_unstable_by(k, f64::total_cmp).1)
        .filter(|v| *v > 0.0)
        .unwrap_or(1.0)
}

/// `x.hypot(y)` by C. F. Borges's corrected square root ("An Improved
/// Algorithm for hypot(a, b)", ACM TOMS 47(1), 2021, algorithm 1014), the
/// method glibc 2.35 and later use, so that on such a system it is the
/// library's `hypot` to the bit (without fused multiply-adds, as x86-64's
/// libm is built), inlined: the band finder takes one at every sample of
/// every band (4.6 % of the ten minutes' time was the calls), and on other
/// systems the strikes no longer depend on their libm. Where one of `x` and `y` is not
/// finite, is past 2^511 or under 2^-459 (none of a recording's levels),
/// `f64::hypot` itself.
#[inline]
pub(super) fn hypot(x: f64, y: f64) -> f64 {
    const LARGE: f64 = f64::from_bits((1023 + 511) << 52);
    const TINY: f64 = f64::from_bits((1023 - 459) << 52);
    const EPS: f64 = f64::from_bits((1023 - 54) << 52);
    let (x, y) = (x.abs(), y.abs());
    let (ax, ay) = if x < y { (y, x) } else { (x, y) };
    if ax.is_nan() || ay.is_nan() || ax > LARGE || ay < TINY {
        return x.hypot(y);
    }
    if ay <= ax * EPS {
        return ax + ay;
    }
    // The root corrected by its residual (Borges's correction).
    let h = (ax * ax + ay * ay).sqrt();
    let (t1, t2) = if h <= 2.0 * ay {
        let d = h - ay;
        (ax * (2.0 * d - ax), (d - 2.0 * (ax - ay)) * d)
    } else {
        let d = h - ax;
        (2.0 * d * (ax - 2.0 * ay), (4.0 * d - ay) * ay + d * d)
    };
    h - (t1 + t2) / (2.0 * h)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Numbers from a small LCG, many of them equal (`levels` of them
    /// from -0.2 to 1), so ties and samples at or under 0 come often.
    fn lcg(n: usize, seed: u64, levels: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((s >> 33) % levels) as f64 / levels as f64 * 1.2 - 0.2
            })
            .collect()
    }

    /// The quick search for peaks finds those the window's first maximum
    /// at every sample finds, ties, flats and the edges included.
    #[test]
    fn peaks_found_by_search_are_those_found_by_window() {
        for seed in 0..300u64 {
            let n = (seed as usize * 37) % 700;
            let levels = [2, 3, 7, 50, 1 << 20][seed as usize % 5];
            let mut v = lcg(n, seed, levels);
            // A smooth stretch (an envelope's rises and falls).
            for k in 1..v.len() / 2 {
                v[k] = 0.7 * v[k - 1] + 0.3 * v[k];
            }
            for sep in [0, 1, 2, 5, 17, 100, 1000] {
                assert_eq!(
                    local_peaks(&v, sep),
                    local_peaks_by_window(&v, sep),
                    "seed {seed}, sep {sep}"
                );
            }
        }
        let v = [0.0, 1.0, f64::NAN, 2.0, 0.5];
        assert_eq!(local_peaks(&v, 1), local_peaks_by_window(&v, 1));
    }

    /// The 90th percentile by selection is sorting's, to the bit.
    #[test]
    fn typical_peak_by_selection_is_by_sorting() {
        for seed in 0..50u64 {
            let v = lcg(500 + seed as usize, seed, 1000);
            let mut h: Vec<f64> = local_peaks(&v, 3).iter().map(|&m| v[m]).collect();
            h.sort_by(f64::total_cmp);
            let sorted = h.get(h.len() * 9 / 10).copied().filter(|v| *v > 0.0).unwrap_or(1.0);
            assert_eq!(typical_peak(&v, 3).to_bits(), sorted.to_bits());
        }
        assert_eq!(typical_peak(&[], 3), 1.0);
        // The crate's median the same: selected, as sorted.
        for seed in 0..50u64 {
            let v = lcg(seed as usize * 3, seed, 20);
            let mut s = v.clone();
            s.sort_by(f64::total_cmp);
            let sorted = s.get(s.len() / 2).copied().unwrap_or(0.0);
            assert_eq!(crate::median(&v).to_bits(), sorted.to_bits());
        }
    }

    /// The inlined `hypot` is the system's (glibc 2.35 or later: its
    /// `hypot` without fused multiply-adds) to the bit, over levels of
    /// every size and ratio, Pythagorean triples exact.
    #[test]
    #[cfg(all(target_os = "linux", target_env = "gnu", target_arch = "x86_64"))]
    fn hypot_inlined_is_the_systems_to_the_bit() {
        let u = lcg(400_000, 7, 1 << 30);
        for (i, w) in u.chunks(2).enumerate() {
            let e = (i % 90) as i32 - 60;
            let (x, y) = (w[0] * 2f64.powi(e), w[1] * 2f64.powi(e - (i % 40) as i32));
            assert_eq!(hypot(x, y).to_bits(), x.hypot(y).to_bits(), "{x:e} {y:e}");
            assert_eq!(hypot(y, -x).to_bits(), y.hypot(-x).to_bits(), "{y:e} {x:e}");
        }
        for (x, y) in [
            (0.0, 0.0),
            (3.0, 4.0),
            (1e300, 1e300),
            (1e-300, 3e-300),
            (f64::INFINITY, f64::NAN),
            (f64::NAN, 1.0),
        ] {
            assert_eq!(hypot(x, y).to_bits(), x.hypot(y).to_bits(), "{x:e} {y:e}");
        }
        assert_eq!(hypot(3.0, 4.0), 5.0);
    }
}
