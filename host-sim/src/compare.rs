//! Image comparison: NMSE (SPEC section 6), PSNR, largest difference, and a
//! heat map of where two images differ.

use crate::heat::heat_color;
use crate::image_io::{read_png, write_png, RgbImage};
use std::path::{Path, PathBuf};

/// How an image differs from a reference of the same size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageDiff {
    /// `sum (I - R)^2 / sum R^2` over every pixel and channel, values as 8-bit
    /// numbers. 0 for identical images; infinite when the reference is all black
    /// and the image is not.
    pub nmse: f64,
    /// Mean squared difference per channel value.
    pub mse: f64,
    /// `10 log10(255^2 / mse)` in dB; infinite for identical images.
    pub psnr_db: f64,
    /// Largest absolute difference of one channel value.
    pub max_abs_diff: u8,
    /// Pixels where at least one channel differs.
    pub differing_pixels: u64,
    /// Pixels compared.
    pub pixels: u64,
    /// `sum (I - R)^2`.
    pub squared_error: u64,
    /// `sum R^2`.
    pub reference_energy: u64,
}

/// Sums of squared differences and squared reference values: NMSE over several
/// images together (frames of an animation) is the ratio of the totals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ErrorSums {
    /// `sum (I - R)^2`.
    pub squared_error: u64,
    /// `sum R^2`.
    pub reference_energy: u64,
    /// Channel values compared.
    pub values: u64,
}

impl ErrorSums {
    /// Adds the sums of one image against its reference (same length, RGB bytes).
    pub fn add(&mut self, image: &[u8], reference: &[u8]) {
        debug_assert_eq!(image.len(), reference.len());
        for (&i, &r) in image.iter().zip(reference) {
            let d = i as i64 - r as i64;
            self.squared_error += (d * d) as u64;
            self.reference_energy += r as u64 * r as u64;
        }
        self.values += image.len().min(reference.len()) as u64;
    }

    /// `squared_error / reference_energy` (0 when both are 0, infinite when only
    /// the reference is 0).
    pub fn nmse(&self) -> f64 {
        ratio(self.squared_error, self.reference_energy)
    }

    /// PSNR in dB over everything added (infinite when nothing differs).
    pub fn psnr_db(&self) -> f64 {
        if self.squared_error == 0 || self.values == 0 {
            return f64::INFINITY;
        }
        let mse = self.squared_error as f64 / self.values as f64;
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

fn ratio(num: u64, den: u64) -> f64 {
    match (num, den) {
        (0, _) => 0.0,
        (_, 0) => f64::INFINITY,
        _ => num as f64 / den as f64,
    }
}

/// NMSE of `image` against `reference`, both RGB888 of the same length.
pub fn nmse(image: &[u8], reference: &[u8]) -> f64 {
    let mut sums = ErrorSums::default();
    sums.add(image, reference);
    sums.nmse()
}

/// Compares two RGB888 images of `width x height` pixels.
pub fn compare_rgb(image: &[u8], reference: &[u8]) -> Result<ImageDiff, String> {
    if image.len() != reference.len() || !image.len().is_multiple_of(3) {
        return Err(format!(
            "images hold {} and {} bytes; both must be the same number of RGB pixels",
            image.len(),
            reference.len()
        ));
    }
    let mut sums = ErrorSums::default();
    sums.add(image, reference);
    let mut max_abs_diff = 0u8;
    let mut differing_pixels = 0u64;
    for (p, q) in image.chunks_exact(3).zip(reference.chunks_exact(3)) {
        let d = channel_diff(p, q);
        max_abs_diff = max_abs_diff.max(d);
        differing_pixels += (d > 0) as u64;
    }
    let values = image.len() as u64;
    Ok(ImageDiff {
        nmse: sums.nmse(),
        mse: if values == 0 {
            0.0
        } else {
            sums.squared_error as f64 / values as f64
        },
        psnr_db: sums.psnr_db(),
        max_abs_diff,
        differing_pixels,
        pixels: values / 3,
        squared_error: sums.squared_error,
        reference_energy: sums.reference_energy,
    })
}

/// Largest absolute difference of the channels of two pixels.
fn channel_diff(p: &[u8], q: &[u8]) -> u8 {
    p.iter()
        .zip(q)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap_or(0)
}

/// A heat map of the differences: black where the images agree, then dark
/// purple through orange to pale yellow as the largest channel difference grows
/// to `scale` (differences above it saturate). `scale` 0 uses the largest
/// difference present.
pub fn diff_heat_map(image: &[u8], reference: &[u8], scale: u8) -> Vec<u8> {
    let diffs: Vec<u8> = image
        .chunks_exact(3)
        .zip(reference.chunks_exact(3))
        .map(|(p, q)| channel_diff(p, q))
        .collect();
    let top = if scale == 0 {
        diffs.iter().copied().max().unwrap_or(0).max(1)
    } else {
        scale
    };
    diffs
        .iter()
        .flat_map(|&d| {
            if d == 0 {
                [0, 0, 0]
            } else {
                heat_color(d.min(top) as f64 / top as f64)
            }
        })
        .collect()
}

/// Arguments of `host-sim compare`.
#[derive(clap::Args, Debug)]
pub struct CompareArgs {
    /// The image to judge (PNG, 8-bit RGB, RGBA or gray; alpha is ignored).
    pub image: PathBuf,
    /// The reference image (same size).
    pub reference: PathBuf,
    /// Write a heat map of the per-pixel differences to this PNG.
    #[arg(long)]
    pub diff: Option<PathBuf>,
    /// Difference that saturates the heat map (0: the largest one present).
    #[arg(long, default_value_t = 0)]
    pub diff_scale: u8,
}

/// Reads both images and checks they have the same size.
pub fn read_pair(image: &Path, reference: &Path) -> Result<(RgbImage, RgbImage), String> {
    let a = read_png(image)?;
    let b = read_png(reference)?;
    if (a.width, a.height) != (b.width, b.height) {
        return Err(format!(
            "images differ in size: {} is {}x{}, {} is {}x{}",
            image.display(),
            a.width,
            a.height,
            reference.display(),
            b.width,
            b.height
        ));
    }
    Ok((a, b))
}

/// Runs `host-sim compare`: prints `NMSE <value>` on its own line, then PSNR,
/// the largest difference and the number of differing pixels.
pub fn run_compare(args: &CompareArgs) -> Result<(), String> {
    let (a, b) = read_pair(&args.image, &args.reference)?;
    let d = compare_rgb(&a.rgb, &b.rgb)?;
    println!("NMSE {}", d.nmse);
    println!("PSNR {:.3} dB", d.psnr_db);
    println!("max abs difference {}", d.max_abs_diff);
    println!(
        "differing pixels {} of {} ({:.3} %)",
        d.differing_pixels,
        d.pixels,
        100.0 * d.differing_pixels as f64 / d.pixels.max(1) as f64
    );
    if let Some(path) = &args.diff {
        let heat = diff_heat_map(&a.rgb, &b.rgb, args.diff_scale);
        write_png(path, a.width, a.height, &heat)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
