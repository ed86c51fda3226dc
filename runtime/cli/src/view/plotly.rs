//! plotly.js, embedded, and the figure the page hands it: plain JSON in plotly.js's own schema
//! (`data`, `layout`, `frames`; <https://plotly.com/javascript/reference/>). The page uses a
//! handful of its trace and layout keys, written here with `serde_json`: the `plotly` crate's
//! typed builders cost a sixth of the program's cold build for the same few lines of JSON
//! (docs/build-time.md).

use serde_json::{json, Value};

/// plotly.js 3.0.1, minified, MIT licence (its header), as the `plotly` crate 0.14 ships it.
pub const PLOTLY_JS: &str = include_str!("../../assets/plotly-3.0.1.min.js");

/// A figure: its traces, its layout and its animation frames.
#[derive(Debug, Default)]
pub struct Figure {
    pub data: Vec<Value>,
    pub layout: Value,
    pub frames: Vec<Value>,
}

impl Figure {
    /// The figure as `Plotly.newPlot` takes it.
    pub fn to_json(&self) -> String {
        json!({"data": self.data, "layout": self.layout, "frames": self.frames}).to_string()
    }
}

/// A `scatter3d` trace through `x`, `y`, `z` in `mode` (`"lines"`, `"markers"`).
pub fn scatter3d(name: &str, mode: &str, [x, y, z]: [Vec<f64>; 3]) -> Value {
    json!({"type": "scatter3d", "name": name, "mode": mode, "x": x, "y": y, "z": z})
}

/// A `mesh3d` trace: vertices, and the triangles' vertex indices where given (an animation
/// frame moves the vertices and keeps the first frame's triangles).
pub fn mesh3d(name: &str, [x, y, z]: [Vec<f64>; 3], triangles: Option<&[[usize; 3]]>) -> Value {
    let mut mesh = json!({"type": "mesh3d", "name": name, "x": x, "y": y, "z": z});
    if let Some(triangles) = triangles {
        for (c, key) in ["i", "j", "k"].into_iter().enumerate() {
            mesh[key] = json!(triangles.iter().map(|t| t[c]).collect::<Vec<_>>());
        }
    }
    mesh
}

/// An animation frame named `name` that replaces the traces `traces` (their indices) by `data`.
pub fn frame(name: &str, data: Vec<Value>, traces: impl IntoIterator<Item = usize>) -> Value {
    json!({"name": name, "data": data, "traces": traces.into_iter().collect::<Vec<_>>()})
}

/// A title object (`{"text": ...}`).
pub fn title(text: &str) -> Value {
    json!({ "text": text })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_library_is_plotly_js() {
        assert!(PLOTLY_JS.starts_with("/**\n* plotly.js v3.0.1"));
        assert!(PLOTLY_JS.contains("Licensed under the MIT license"));
        assert!(
            !PLOTLY_JS.contains("</script"),
            "it could not sit in a <script> element"
        );
    }

    #[test]
    fn a_mesh_without_triangles_keeps_the_first_frames() {
        let xyz = [vec![0.0, 1.0, 0.0], vec![0.0, 0.0, 1.0], vec![0.0; 3]];
        let with = mesh3d("m", xyz.clone(), Some(&[[0, 1, 2]]));
        assert_eq!(
            (&with["i"], &with["j"], &with["k"]),
            (&json!([0]), &json!([1]), &json!([2]))
        );
        assert!(mesh3d("m", xyz, None).get("i").is_none());
    }
}
