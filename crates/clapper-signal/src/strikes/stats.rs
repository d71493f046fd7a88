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
/// either side (ties to the earliest).
pub(super) fn local_peaks(v: &[f64], sep: usize) -> Vec<usize> {
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
    h.sort_by(f64::total_cmp);
    h.get(h.len() * 9 / 10).copied().filter(|v| *v > 0.0).unwrap_or(1.0)
}
