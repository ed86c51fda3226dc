//! What `c5 calibrate` tells: the text report, its JSON twin, and the residuals' figure.

use crate::simulate::register_font;
use crate::Result;
use c5_runtime::calibrate::{Options, Report, Spread};
use plotters::prelude::*;
use std::fmt::Write;
use std::path::Path;

fn um(x: f64) -> f64 {
    x * 1e6
}

/// The residuals' small unit: µm for lengths, µrad for motors' angles.
fn micro(report: &Report) -> &'static str {
    if report.angular {
        "µrad"
    } else {
        "µm"
    }
}

/// The root mean square over the legs of each leg's rms.
fn all(x: &[Spread]) -> f64 {
    (x.iter().map(|s| s.rms * s.rms).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// The report as text: residuals per leg before and after, each parameter with its change
/// and standard deviation, the observability and what the data cannot separate.
pub fn text(report: &Report, options: &Options) -> Result<String> {
    let mut s = String::new();
    let n = report.residuals_before.len();
    writeln!(
        s,
        "{n} measured poses; {} iterations; variance factor {:.3} (about 1 when the stated noise \
         is right: {:.1} µm, {:.1} µrad, encoders {:.2} {unit})",
        report.iterations,
        report.variance_factor,
        um(options.noise.position),
        um(options.noise.angle),
        um(options.noise.encoder),
        unit = micro(report),
    )?;
    writeln!(
        s,
        "\nresiduals q(X) - q̂ per leg ({:<4})  nominal rms / max    calibrated rms / max",
        micro(report)
    )?;
    let (before, after) = (report.before(), report.after());
    for (leg, (b, a)) in before.iter().zip(&after).enumerate() {
        writeln!(
            s,
            "  leg {}                           {:>9.1} / {:<9.1}  {:>8.2} / {:<8.2}",
            leg + 1,
            um(b.rms),
            um(b.max),
            um(a.rms),
            um(a.max)
        )?;
    }
    writeln!(
        s,
        "  all legs                        {:>9.1}               {:>8.2}",
        um(all(&before)),
        um(all(&after))
    )?;
    writeln!(
        s,
        "\nparameters (mm, or mrad for an angle): A_i base joint or motor centre (base frame), \
         r_i.az and r_i.el the motor axis's azimuth and elevation, p_i platform joint centre \
         (platform frame), c_i crank and L_i rod length, o_i encoder offset"
    )?;
    writeln!(s, "  name        nominal     estimate    change      σ")?;
    for p in &report.parameters {
        let sigma = p.std_dev.map_or("fixed (not observable)".to_string(), |d| {
            format!("{:.4}", d * 1e3)
        });
        writeln!(
            s,
            "  {:<7} {:>11.4} {:>12.4} {:>+9.4} {:>10}",
            p.name,
            p.nominal * 1e3,
            p.estimate * 1e3,
            (p.estimate - p.nominal) * 1e3,
            sigma
        )?;
    }
    writeln!(
        s,
        "\nobservability: singular values of each leg's whitened Jacobian, parameters scaled by \
         {} mm (1/σ is a combination's standard deviation in scales)",
        options.scale * 1e3
    )?;
    for (leg, sv) in report.singular_values.iter().enumerate() {
        let condition = sv.first().unwrap_or(&0.0) / sv.last().unwrap_or(&0.0);
        let values: Vec<String> = sv.iter().map(|v| format!("{v:.3e}")).collect();
        writeln!(
            s,
            "  leg {}: {}  (condition {:.1})",
            leg + 1,
            values.join(" "),
            condition
        )?;
    }
    if report.unobservable.is_empty() {
        writeln!(s, "every parameter is observable from these measurements")?;
    } else {
        writeln!(
            s,
            "not observable (σ above {} mm or mrad), fixed at nominal instead of smeared:",
            options.observable * 1e3
        )?;
        for u in &report.unobservable {
            writeln!(s, "  {u}")?;
        }
    }
    Ok(s)
}

/// The report as JSON.
pub fn json(report: &Report) -> serde_json::Value {
    let spread = |x: Vec<Spread>| {
        x.iter()
            .map(|s| serde_json::json!({"rms": s.rms, "max": s.max}))
            .collect::<Vec<_>>()
    };
    serde_json::json!({
        "measurements": report.residuals_before.len(),
        "iterations": report.iterations,
        "variance_factor": report.variance_factor,
        "unit": if report.angular { "rad" } else { "m" },
        "before": spread(report.before()),
        "after": spread(report.after()),
        "parameters": report.parameters.iter().map(|p| serde_json::json!({
            "name": p.name, "leg": p.leg, "unit": if p.angle { "rad" } else { "m" },
            "nominal": p.nominal,
            "estimate": p.estimate, "std_dev": p.std_dev,
        })).collect::<Vec<_>>(),
        "singular_values": report.singular_values,
        "unobservable": report.unobservable.iter().map(|u| serde_json::json!({
            "leg": u.leg, "combination": u.combination, "std_dev": u.std_dev, "fixed": u.fixed,
        })).collect::<Vec<_>>(),
    })
}

/// Each leg's residual at each measurement, nominal (mm or mrad, top) and calibrated (µm or
/// µrad, bottom).
pub fn plot(path: &Path, report: &Report) -> Result<()> {
    register_font();
    crate::png_figure::write(path, (1000, 760), |root| {
        root.fill(&WHITE)?;
        let panels = root.split_evenly((2, 1));
        let n = report.residuals_before.len();
        let (milli, micro) = if report.angular {
            ("residual (mrad)", "residual (µrad)")
        } else {
            ("residual (mm)", "residual (µm)")
        };
        for (panel, (rows, title, unit, factor)) in panels.iter().zip([
            (
                &report.residuals_before,
                "Nominal geometry: residuals q(X) - q̂",
                milli,
                1e3,
            ),
            (
                &report.residuals_after,
                "Calibrated geometry: residuals q(X) - q̂",
                micro,
                1e6,
            ),
        ]) {
            let peak = rows
                .iter()
                .flatten()
                .fold(0.0f64, |m, r| m.max(r.abs() * factor))
                .max(1e-12)
                * 1.1;
            let mut chart = ChartBuilder::on(panel)
                .caption(title, ("sans-serif", 20))
                .margin(10)
                .x_label_area_size(36)
                .y_label_area_size(64)
                .build_cartesian_2d(0.5..n as f64 + 0.5, -peak..peak)?;
            chart
                .configure_mesh()
                .x_desc("measurement")
                .x_label_formatter(&|x| format!("{x:.0}"))
                .y_desc(unit)
                .label_style(("sans-serif", 14))
                .draw()?;
            for leg in 0..report.legs() {
                let color = Palette99::pick(leg).to_rgba();
                let points = rows
                    .iter()
                    .enumerate()
                    .map(|(k, r)| ((k + 1) as f64, r[leg] * factor));
                chart
                    .draw_series(LineSeries::new(points.clone(), color.stroke_width(1)))?
                    .label(format!("leg {}", leg + 1))
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                chart.draw_series(points.map(|p| Circle::new(p, 2, color.filled())))?;
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 13))
                .draw()?;
        }
        Ok(())
    })
}
