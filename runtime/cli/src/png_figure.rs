//! PNG figures: plotters draws into an RGB buffer and the `png` crate writes it. Plotters'
//! own PNG output goes through the `image` crate, which would be a tenth of the program's cold
//! build for one encoder (docs/build-time.md).

use plotters::coord::Shift;
use plotters::prelude::{BitMapBackend, DrawingArea, IntoDrawingArea};
use std::io::BufWriter;
use std::path::Path;

/// Draws a figure of `size` pixels with `draw` and writes it to `path` as an 8-bit RGB PNG.
///
/// # Errors
/// What `draw` returns, or a file that cannot be written.
pub fn write<F>(path: &Path, size: (u32, u32), draw: F) -> crate::Result<()>
where
    F: for<'b> FnOnce(DrawingArea<BitMapBackend<'b>, Shift>) -> crate::Result<()>,
{
    let (width, height) = size;
    let mut pixels = vec![0u8; 3 * width as usize * height as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
        draw(root.clone())?;
        root.present()?;
    }
    let file = BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    // Plots are mostly flat colour: filtering and a thorough deflate make them ten times
    // smaller than the crate's fast default, in a few milliseconds more.
    encoder.set_compression(png::Compression::Best);
    encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    encoder.write_header()?.write_image_data(&pixels)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::{Color, RED, WHITE};

    #[test]
    fn the_figure_reads_back_as_drawn() {
        let path = std::env::temp_dir().join(format!("c5-png-{}.png", std::process::id()));
        write(&path, (40, 30), |root| {
            root.fill(&WHITE)?;
            let (left, _) = root.split_horizontally(10);
            left.fill(&RED.to_rgba())?;
            Ok(())
        })
        .unwrap();
        let decoder = png::Decoder::new(std::fs::File::open(&path).unwrap());
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!((info.width, info.height), (40, 30));
        assert_eq!(info.color_type, png::ColorType::Rgb);
        let at = |x: usize, y: usize| &buf[3 * (y * 40 + x)..3 * (y * 40 + x) + 3];
        assert_eq!(at(5, 15), [255, 0, 0]);
        assert_eq!(at(30, 15), [255, 255, 255]);
    }
}
