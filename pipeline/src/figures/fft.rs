//! In-place radix-2 FFT (iterative Cooley–Tukey), enough for the spectra of figures: no
//! dependency, O(n log n), n a power of two.

use super::FigureError;
use std::f64::consts::PI;

/// Forward DFT `X_k = Σ_j x_j e^{-2πi jk/n}` of `(re, im)` in place.
///
/// Errors when the lengths differ or `n` is not a power of two (zero-pad first).
pub fn fft_in_place(re: &mut [f64], im: &mut [f64]) -> Result<(), FigureError> {
    let n = re.len();
    if im.len() != n || !n.is_power_of_two() {
        return Err(FigureError::Spectrum(format!(
            "FFT needs equal power-of-two lengths, got re {n}, im {}",
            im.len()
        )));
    }
    // Bit-reversal permutation.
    let mut j = 0usize;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    // Butterflies; twiddles by direct cos/sin per stage (accurate, no recurrence drift).
    let mut len = 2;
    while len <= n {
        let half = len / 2;
        let (tw_re, tw_im): (Vec<f64>, Vec<f64>) = (0..half)
            .map(|k| {
                let a = -2.0 * PI * k as f64 / len as f64;
                (a.cos(), a.sin())
            })
            .unzip();
        for start in (0..n).step_by(len) {
            for k in 0..half {
                let (a, b) = (start + k, start + k + half);
                let (wr, wi) = (tw_re[k], tw_im[k]);
                let tr = re[b] * wr - im[b] * wi;
                let ti = re[b] * wi + im[b] * wr;
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
            }
        }
        len <<= 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the O(n²) definition of the DFT, on a non-symmetric complex input.
    #[test]
    fn fft_matches_direct_dft() {
        let n = 64;
        let x_re: Vec<f64> = (0..n)
            .map(|j| ((j * j) as f64 * 0.37).sin() + 0.1 * j as f64)
            .collect();
        let x_im: Vec<f64> = (0..n).map(|j| (j as f64 * 1.3).cos()).collect();
        let (mut re, mut im) = (x_re.clone(), x_im.clone());
        fft_in_place(&mut re, &mut im).unwrap();
        for k in 0..n {
            let (mut sr, mut si) = (0.0, 0.0);
            for j in 0..n {
                let a = -2.0 * PI * (j * k) as f64 / n as f64;
                sr += x_re[j] * a.cos() - x_im[j] * a.sin();
                si += x_re[j] * a.sin() + x_im[j] * a.cos();
            }
            assert!(
                (re[k] - sr).abs() < 1e-10 && (im[k] - si).abs() < 1e-10,
                "bin {k}"
            );
        }
        let mut bad = vec![0.0; 12];
        assert!(fft_in_place(&mut bad.clone(), &mut bad).is_err());
    }
}
