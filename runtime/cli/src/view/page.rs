//! The page: plotly.js embedded, the figure and the per-frame readout as JSON, and a few lines
//! of script for play, pause and the time slider. It loads nothing: no server, no network.

use super::figure::Readout;
use super::plotly::{Figure, PLOTLY_JS};

/// JSON that cannot end the `<script>` element it sits in.
fn embeddable(json: String) -> String {
    json.replace("</", "<\\/")
}

/// The whole page; `unit` is the actuator forces' (`N`, `N·m`).
pub fn page(
    title: &str,
    note: &str,
    plot: &Figure,
    readout: &[Readout],
    unit: &str,
) -> Result<String, serde_json::Error> {
    let figure = embeddable(plot.to_json());
    let readout = embeddable(serde_json::to_string(readout)?);
    let title = html_escape(title);
    let note = html_escape(note);
    let unit = html_escape(unit);
    Ok(format!(
        r#"<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ font: 14px system-ui, sans-serif; margin: 0; color: #222; }}
header {{ padding: 8px 14px 0; }}
h1 {{ font-size: 17px; margin: 0 0 2px; }}
.note {{ color: #555; margin: 0; }}
#controls {{ display: flex; gap: 10px; align-items: center; padding: 6px 14px; }}
#slider {{ flex: 1; }}
#time {{ font-variant-numeric: tabular-nums; min-width: 7em; }}
#forces {{ border-collapse: collapse; margin: 0 14px; font-variant-numeric: tabular-nums; }}
#forces td {{ padding: 1px 10px 1px 4px; }}
.swatch {{ display: inline-block; width: 12px; height: 12px; border-radius: 2px; margin-right: 4px; vertical-align: -1px; }}
#warnings {{ color: #b0008a; padding: 2px 14px; min-height: 1.3em; }}
#figure {{ width: 100%; height: calc(100vh - 150px); min-height: 420px; }}
</style>
{plotly_js}
</head>
<body>
<header><h1>{title}</h1><p class="note">{note}</p></header>
<div id="controls">
<button id="play" type="button">Play</button>
<input id="slider" type="range" min="0" value="0" step="1" aria-label="time">
<span id="time"></span>
</div>
<table id="forces" data-unit="{unit}"><tr id="force-cells"></tr></table>
<div id="warnings"></div>
<div id="figure"></div>
<script id="c5-figure" type="application/json">{figure}</script>
<script id="c5-readout" type="application/json">{readout}</script>
<script>
{SCRIPT}
</script>
</body>
</html>
"#,
        plotly_js = format_args!("<script type=\"text/javascript\">{PLOTLY_JS}</script>"),
    ))
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Play, pause, the slider and the readout; `window.c5view` lets a test drive the page.
const SCRIPT: &str = r#"(function () {
  const figure = JSON.parse(document.getElementById("c5-figure").textContent);
  const readout = JSON.parse(document.getElementById("c5-readout").textContent);
  const div = document.getElementById("figure");
  const slider = document.getElementById("slider");
  const play = document.getElementById("play");
  const cells = document.getElementById("force-cells");
  const unit = document.getElementById("forces").dataset.unit;
  const n = readout.length;
  slider.max = String(n - 1);
  const view = { frames: n, readout: readout, ready: false, shown: -1, show: show };
  window.c5view = view;
  if (n === 0) {
    document.getElementById("controls").style.display = "none";
    Plotly.newPlot(div, figure).then(function () { view.ready = true; });
    return;
  }
  let timer = null;
  const step = n > 1 ? (readout[n - 1].t - readout[0].t) / (n - 1) : 0;
  const delay = Math.max(40, 1000 * step);

  function describe(k) {
    const r = readout[k];
    document.getElementById("time").textContent = "t = " + r.t.toFixed(3) + " s";
    cells.innerHTML = "";
    r.gamma.forEach(function (g, i) {
      const td = document.createElement("td");
      td.innerHTML = '<span class="swatch" style="background:' + r.colours[i] + '"></span>' +
        "Γ" + (i + 1) + " = " + g.toFixed(2) + " " + unit;
      cells.appendChild(td);
    });
    document.getElementById("warnings").textContent =
      r.warnings.length ? "past a limit: " + r.warnings.join("; ") : "";
  }

  function show(k) {
    k = Math.max(0, Math.min(n - 1, k | 0));
    slider.value = String(k);
    describe(k);
    return Plotly.animate(div, [String(k)], {
      mode: "immediate",
      frame: { duration: 0, redraw: true },
      transition: { duration: 0 },
    }).then(function () { view.shown = k; });
  }

  function stop() {
    if (timer !== null) { clearTimeout(timer); timer = null; }
    play.textContent = "Play";
  }

  function tick() {
    const next = Number(slider.value) + 1;
    if (next >= n) { stop(); return; }
    show(next).then(function () {
      if (timer !== null) { timer = setTimeout(tick, delay); }
    });
  }

  play.addEventListener("click", function () {
    if (timer !== null) { stop(); return; }
    if (Number(slider.value) >= n - 1) { slider.value = "0"; }
    play.textContent = "Pause";
    timer = setTimeout(tick, 0);
  });
  slider.addEventListener("input", function () { stop(); show(Number(slider.value)); });

  Plotly.newPlot(div, figure).then(function () {
    return show(0);
  }).then(function () { view.ready = true; });
})();"#;
