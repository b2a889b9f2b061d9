//! Figures: every builder writes a PNG of the asked size and an SVG carrying its texts; the
//! spectrum finds known frequencies in non-uniformly sampled data; bad data is an error.

use squeal_pipeline::figures::{
    amplitude_spectrum, grouped_bars, root_locus, spectrum, stability_map, time_history,
    work_precision, write_figure, Figure, FigureError, FigureFiles, Series, SeriesStyle,
    SpectrumOptions,
};
use std::f64::consts::PI;
use std::path::PathBuf;

fn out_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("figures")
}

/// Checks the PNG signature and that the IHDR chunk (the PNG spec puts it first: length,
/// "IHDR", width, height as big-endian u32) gives `size`; checks the SVG holds each text.
fn check_files(files: &FigureFiles, size: (u32, u32), texts: &[&str]) {
    let png = std::fs::read(&files.png).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n", "{}", files.png.display());
    assert_eq!(&png[12..16], b"IHDR");
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
    assert_eq!((w, h), size);
    // A blank white image of this size deflates to a few kB; text and curves add far more.
    assert!(png.len() > 10_000, "PNG of only {} bytes", png.len());
    let svg = std::fs::read_to_string(&files.svg).unwrap();
    assert!(svg.starts_with("<svg") || svg.contains("<svg"));
    assert!(svg.contains(&format!("width=\"{}\"", size.0)));
    for t in texts {
        assert!(svg.contains(t), "SVG {} lacks {t:?}", files.svg.display());
    }
}

#[test]
fn time_history_writes_png_and_svg_zoomed_on_a_window() {
    let t: Vec<f64> = (0..2000).map(|i| i as f64 * 5e-4).collect();
    let growing: Vec<f64> = t
        .iter()
        .map(|&t| (0.8 * t).exp() * (2.0 * PI * 12.0 * t).sin())
        .collect();
    let decaying: Vec<f64> = t
        .iter()
        .map(|&t| (-0.5 * t).exp() * (2.0 * PI * 5.0 * t).cos())
        .collect();
    let curves = [("pad node 12 z", growing), ("rotor node 7 z", decaying)];
    let mut fig = time_history("Transient response", &t, &curves, Some((0.75, 1.0)));
    fig.size = (800, 500);
    let files = write_figure(&fig, &out_dir().join("time_history"))
        .unwrap()
        .unwrap();
    check_files(
        &files,
        (800, 500),
        &[
            "Transient response",
            "time (s)",
            "response",
            "pad node 12 z",
        ],
    );
}

#[test]
fn stability_map_writes_files_with_both_groups() {
    let modes = [
        (850.0, -12.0, false),
        (2400.0, 35.0, true),
        (2410.0, -35.0, false),
        (7800.0, 0.0, false),
    ];
    let fig = stability_map(&modes);
    assert_eq!(fig.series.len(), 2);
    assert_eq!(fig.series[1].x, vec![2400.0]);
    let files = write_figure(&fig, &out_dir().join("stability_map"))
        .unwrap()
        .unwrap();
    check_files(
        &files,
        fig.size,
        &[
            "Stability map",
            "frequency (Hz)",
            "real part (1/s)",
            "unstable",
        ],
    );
}

#[test]
fn root_locus_writes_both_panels() {
    // Two modes coalescing at μ = 0.3 (the 2-DOF mode-coupling picture): below it two
    // frequencies and zero real part, above it one frequency and real parts ±.
    let mus: Vec<f64> = (0..=10).map(|i| 0.05 * i as f64).collect();
    let track = |sign: f64| -> Vec<(f64, f64, f64)> {
        mus.iter()
            .map(|&mu| {
                let d = mu - 0.3;
                if d < 0.0 {
                    (mu, 2000.0 + sign * 400.0 * (-d).sqrt(), 0.0)
                } else {
                    (mu, 2000.0, sign * 300.0 * d.sqrt())
                }
            })
            .collect()
    };
    let tracks = [("mode 5", track(1.0)), ("mode 6", track(-1.0))];
    let (by_f, by_mu) = root_locus(&tracks);
    let a = write_figure(&by_f, &out_dir().join("root_locus_freq"))
        .unwrap()
        .unwrap();
    check_files(
        &a,
        by_f.size,
        &[
            "Root locus",
            "frequency (Hz)",
            "real part (1/s)",
            "mode 5",
            "mode 6",
        ],
    );
    let b = write_figure(&by_mu, &out_dir().join("root_locus_mu"))
        .unwrap()
        .unwrap();
    check_files(
        &b,
        by_mu.size,
        &["Root locus against μ", "friction coefficient μ", "mode 6"],
    );
}

#[test]
fn work_precision_is_log_log_with_decade_ticks() {
    // error = C·cpu^-2 (a second-order method), over 6 decades of error.
    let run = |c: f64| -> Vec<(f64, f64)> {
        (0..7)
            .map(|i| 0.01 * 10f64.powf(0.5 * i as f64))
            .map(|s| (s, c * s.powi(-2)))
            .collect()
    };
    let runs = [("BDF2", run(1e-6)), ("BDF1", run(1e-4))];
    let fig = work_precision(&runs);
    let files = write_figure(&fig, &out_dir().join("work_precision"))
        .unwrap()
        .unwrap();
    // Decade tick labels are 10ⁿ (the y data spans 1e-12 .. 1e0).
    check_files(
        &files,
        fig.size,
        &["Work–precision", "CPU time (s)", "error", "BDF1", "10⁻⁶"],
    );
}

/// y(t) = Σ A_k sin(2π f_k t + φ_k) with f = 1, 2, 3 kHz (a fundamental and two harmonics),
/// sampled at irregular times like an adaptive integrator's; the amplitudes and frequencies are
/// the reference. Mean step 1e-5 s, longest 1.5e-5 s: at 3 kHz linear interpolation loses at
/// most (ωh)²/8 = 1.0 % of the amplitude; with 4× zero padding Hann's scalloping loss is
/// below 0.1 dB (1.1 %) before the parabolic refinement.
#[test]
fn spectrum_of_nonuniform_sum_of_sines_finds_the_harmonics() {
    // A 4th harmonic at 1 % of the fundamental (−40 dB) must be found too.
    let comps = [
        (1000.0, 1.0, 0.3),
        (2000.0, 0.5, 1.1),
        (3000.0, 0.25, 2.0),
        (4000.0, 0.01, 0.5),
    ];
    let mut t = vec![0.0];
    let mut i = 0usize;
    while *t.last().unwrap() < 0.05 {
        let h = 1e-5 * (1.0 + 0.5 * (1.7 * i as f64).sin());
        t.push(t.last().unwrap() + h);
        i += 1;
    }
    let y: Vec<f64> = t
        .iter()
        .map(|&t| {
            0.7 + comps
                .iter()
                .map(|(f, a, p)| a * (2.0 * PI * f * t + p).sin())
                .sum::<f64>()
        })
        .collect();
    // Default options ask for 5 peaks: only the 4 components may come back, not the side lobes
    // of the large ones (Hann's reach 2.7 % of their peak, above the 4th harmonic).
    let opts = SpectrumOptions::default();
    let s = amplitude_spectrum(&t, &y, &opts).unwrap();
    assert_eq!(s.peaks.len(), 4, "{:?}", s.peaks);
    for (peak, (f, a, _)) in s.peaks.iter().zip(&comps) {
        assert!(
            (peak.freq_hz - f).abs() < s.df_hz,
            "peak {peak:?} vs {f} Hz, bin {} Hz",
            s.df_hz
        );
        assert!(
            (peak.amplitude / a - 1.0).abs() < 0.02,
            "peak {peak:?} vs amplitude {a}"
        );
    }
    // Harmonics: the next peaks are at 2×, 3×, 4× the fundamental within one bin.
    let f0 = s.peaks[0].freq_hz;
    for (k, p) in [(2.0, s.peaks[1]), (3.0, s.peaks[2]), (4.0, s.peaks[3])] {
        assert!((p.freq_hz - k * f0).abs() < s.df_hz);
    }
    let (mut fig, _) = spectrum(
        &t,
        &y,
        &SpectrumOptions {
            f_max_hz: Some(5000.0),
            ..opts
        },
    )
    .unwrap();
    fig.title = "Spectrum of pad node 12 z".into();
    let files = write_figure(&fig, &out_dir().join("spectrum"))
        .unwrap()
        .unwrap();
    check_files(
        &files,
        fig.size,
        &[
            "Spectrum of pad node 12 z",
            "frequency (Hz)",
            "amplitude",
            "peaks",
        ],
    );
}

#[test]
fn nan_and_empty_data_are_errors_not_panics() {
    let dir = out_dir().join("errors");
    let mut fig = Figure::new("bad", "x", "y");
    fig.series.push(Series::new(
        "s",
        vec![0.0, 1.0, 2.0],
        vec![0.0, f64::NAN, 1.0],
        SeriesStyle::Line,
    ));
    match write_figure(&fig, &dir.join("nan")) {
        Err(FigureError::NonFinite {
            axis: "y",
            index: 1,
            ..
        }) => {}
        other => panic!("expected NonFinite y[1], got {other:?}"),
    }
    assert!(!dir.join("nan.png").exists());

    let empty = Figure::new("empty", "x", "y");
    assert!(matches!(
        write_figure(&empty, &dir.join("empty")),
        Err(FigureError::NoSeries { .. })
    ));
    let mut no_points = Figure::new("no points", "x", "y");
    no_points
        .series
        .push(Series::new("s", vec![], vec![], SeriesStyle::Points));
    assert!(matches!(
        write_figure(&no_points, &dir.join("np")),
        Err(FigureError::EmptySeries { .. })
    ));

    let mut log0 = work_precision(&[("run", vec![(1.0, 1e-3), (2.0, 0.0)])]);
    log0.title = "log zero".into();
    assert!(matches!(
        write_figure(&log0, &dir.join("log0")),
        Err(FigureError::NonPositiveOnLog {
            axis: "y",
            index: 1,
            ..
        })
    ));

    let t = [0.0, 1.0, 2.0, 3.0, 4.0];
    let y = [0.0, 1.0, f64::INFINITY, 1.0, 0.0];
    assert!(matches!(
        amplitude_spectrum(&t, &y, &SpectrumOptions::default()),
        Err(FigureError::Spectrum(_))
    ));
    let backwards = [0.0, 1.0, 0.5, 3.0, 4.0];
    assert!(matches!(
        amplitude_spectrum(&backwards, &t, &SpectrumOptions::default()),
        Err(FigureError::Spectrum(_))
    ));
    let rev = time_history(
        "reversed window",
        &t,
        &[("y", t.to_vec())],
        Some((3.0, 1.0)),
    );
    assert!(matches!(
        write_figure(&rev, &dir.join("rev")),
        Err(FigureError::BadRange { axis: "x", .. })
    ));
}

#[test]
fn constant_data_gets_a_widened_range() {
    let t = [0.0, 1.0, 2.0];
    let fig = time_history("Constant signal", &t, &[("flat", [3.5, 3.5, 3.5])], None);
    let files = write_figure(&fig, &out_dir().join("constant"))
        .unwrap()
        .unwrap();
    check_files(&files, fig.size, &["Constant signal", "flat"]);
}

/// Grouped bars (the energy shares of a mode): two groups side by side per category, filled
/// rectangles in the SVG, the categories named in the x label.
#[test]
fn grouped_bars_draw_filled_rectangles_side_by_side() {
    let cats = vec![
        "rotor".to_string(),
        "pad".to_string(),
        "caliper".to_string(),
    ];
    let groups = [
        ("kinetic energy share", vec![0.2, 0.25, 0.05]),
        ("strain energy share", vec![0.3, 0.1, 0.1]),
    ];
    let fig = grouped_bars("Mode 3 shares", &cats, "share", &groups);
    let files = write_figure(&fig, &out_dir().join("bars"))
        .unwrap()
        .unwrap();
    check_files(
        &files,
        fig.size,
        &[
            "Mode 3 shares",
            "0 = rotor, 1 = pad, 2 = caliper",
            "strain energy share",
        ],
    );
    let svg = std::fs::read_to_string(&files.svg).unwrap();
    // 6 bars beside the page background and the legend box.
    let rects = svg.matches("<rect").count();
    assert!(rects > 6, "{rects} rects");
}
