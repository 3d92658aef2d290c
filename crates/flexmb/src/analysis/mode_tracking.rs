//! Following modes along a parameter sweep (a Campbell diagram) by their shapes: each mode at one
//! value is matched with the mode at the previous value whose shape it resembles most, by the modal
//! assurance criterion of complex shapes (Allemang 2003),
//!
//! ```text
//! MAC(φ, ψ) = |φᴴ ψ|² / ((φᴴ φ)(ψᴴ ψ))
//! ```
//!
//! 1 for shapes equal up to a complex factor (a phase and a scale), 0 for orthogonal ones. A forward
//! and a backward whirl of the same tilt (`(1, i)` against `(1, −i)` in two transverse rotations) have
//! MAC 0, so that curves that cross keep their whirl, where sorting by frequency would swap them. The
//! shapes compared are in velocity coordinates (`δx = N δz`), the same at every value of the sweep
//! whichever independent coordinates the partition chooses.
//!
//! The assignment is greedy on the whole table: the pair (track, mode) of largest MAC first, ties
//! broken by the nearer frequency, until the tracks or the modes run out. With a few tens of modes and
//! a fine enough sweep the largest MAC of each row is far above the others (near 1 against near 0),
//! and a greedy assignment is the optimal one.

use super::{EigenAnalysis, Mode};

/// The modal assurance criterion of two complex shapes given by their real and imaginary parts:
/// `|φᴴ ψ|² / ((φᴴ φ)(ψᴴ ψ))`, in `[0, 1]`; 0 when either shape is zero.
pub fn modal_assurance(phi_re: &[f64], phi_im: &[f64], psi_re: &[f64], psi_im: &[f64]) -> f64 {
    let (mut re, mut im, mut pp, mut ss) = (0.0, 0.0, 0.0, 0.0);
    for k in 0..phi_re.len() {
        let (a, b, c, d) = (phi_re[k], phi_im[k], psi_re[k], psi_im[k]);
        // conj(a + ib)(c + id) = (ac + bd) + i(ad − bc)
        re += a * c + b * d;
        im += a * d - b * c;
        pp += a * a + b * b;
        ss += c * c + d * d;
    }
    if pp == 0.0 || ss == 0.0 {
        return 0.0;
    }
    (re * re + im * im) / (pp * ss)
}

/// The oscillating (not rigid-body) modes of a sweep followed from value to value: `tracks[k][i]` is
/// the index in `sweep[i].modes` of track `k`'s mode at value `i` (`None` where the track has no
/// mode there). The tracks start as the oscillating modes of the first value, by increasing
/// frequency; a mode that matches no track (more modes than before) starts a new one.
pub fn track_modes(sweep: &[EigenAnalysis]) -> Vec<Vec<Option<usize>>> {
    let mut tracks: Vec<Vec<Option<usize>>> = Vec::new();
    // The last mode each track was matched to: (value index, mode index).
    let mut last: Vec<(usize, usize)> = Vec::new();
    for (i, analysis) in sweep.iter().enumerate() {
        let modes: Vec<usize> = (0..analysis.modes.len()).filter(|&m| !analysis.modes[m].rigid_body).collect();
        let mut pairs: Vec<(f64, f64, usize, usize)> = Vec::new();
        for (k, &(j, previous)) in last.iter().enumerate() {
            let before = &sweep[j].modes[previous];
            for &m in &modes {
                let now = &analysis.modes[m];
                pairs.push((shape_assurance(before, now), (before.frequency - now.frequency).abs(), k, m));
            }
        }
        pairs.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.total_cmp(&b.1)));
        let mut row: Vec<Option<usize>> = vec![None; tracks.len()];
        let mut taken = vec![false; analysis.modes.len()];
        for (_, _, k, m) in pairs {
            if row[k].is_none() && !taken[m] {
                row[k] = Some(m);
                taken[m] = true;
            }
        }
        for (k, entry) in row.iter().enumerate() {
            tracks[k].push(*entry);
            if let Some(m) = entry {
                last[k] = (i, *m);
            }
        }
        for &m in modes.iter().filter(|&&m| !taken[m]) {
            let mut track = vec![None; i];
            track.push(Some(m));
            tracks.push(track);
            last.push((i, m));
        }
    }
    tracks
}

fn shape_assurance(a: &Mode, b: &Mode) -> f64 {
    modal_assurance(&a.shape_re, &a.shape_im, &b.shape_re, &b.shape_im)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::Whirl;

    fn mode(frequency: f64, re: [f64; 2], im: [f64; 2]) -> Mode {
        Mode {
            eigenvalue: (0.0, frequency),
            frequency,
            damped_frequency: frequency,
            damping_ratio: 0.0,
            rigid_body: false,
            whirl: Whirl::None,
            shape_re: re.to_vec(),
            shape_im: im.to_vec(),
            independent_re: re.to_vec(),
            independent_im: im.to_vec(),
        }
    }

    /// A shape times any complex factor has MAC 1 with it; a forward and a backward circular orbit
    /// have MAC 0; a straight orbit has MAC ½ with each.
    #[test]
    fn the_assurance_criterion_ignores_phase_and_scale_and_tells_whirl_apart() {
        let (re, im) = ([1.0, 0.3], [0.2, -0.5]);
        // (2 − 3i)(re + i im)
        let (sre, sim): (Vec<f64>, Vec<f64>) = (0..2).map(|k| (2.0 * re[k] + 3.0 * im[k], 2.0 * im[k] - 3.0 * re[k])).unzip();
        assert!((modal_assurance(&re, &im, &sre, &sim) - 1.0).abs() < 1e-15);
        assert_eq!(modal_assurance(&[1.0, 0.0], &[0.0, 1.0], &[1.0, 0.0], &[0.0, -1.0]), 0.0);
        assert!((modal_assurance(&[1.0, 0.0], &[0.0, 0.0], &[1.0, 0.0], &[0.0, 1.0]) - 0.5).abs() < 1e-15);
    }

    /// Two modes that cross in frequency (one rising, one falling) with shapes that do not change: the
    /// tracks follow the shapes through the crossing, where sorting would swap them.
    #[test]
    fn crossing_modes_keep_their_tracks() {
        let point = |fa: f64, fb: f64| EigenAnalysis {
            modes: {
                let (a, b) = (mode(fa, [1.0, 0.0], [0.0, 1.0]), mode(fb, [1.0, 0.0], [0.0, -1.0]));
                if fa < fb { vec![a, b] } else { vec![b, a] }
            },
            spin: None,
        };
        let sweep = [point(1.0, 3.0), point(2.0, 2.5), point(3.0, 2.0), point(4.0, 1.5)];
        let tracks = track_modes(&sweep);
        let frequencies: Vec<Vec<f64>> = tracks.iter().map(|t| t.iter().enumerate().map(|(i, m)| sweep[i].modes[m.unwrap()].frequency).collect()).collect();
        assert_eq!(frequencies, vec![vec![1.0, 2.0, 3.0, 4.0], vec![3.0, 2.5, 2.0, 1.5]]);
    }
}
