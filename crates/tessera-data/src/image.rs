//! RGBA8 images as the techniques produce them, and the tolerant comparison tests use.

/// Pixels packed as `r | g << 8 | b << 16 | a << 24`, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u32>,
}

/// How two images differ.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageDiff {
    /// Largest per-channel difference over all pixels.
    pub max_channel_diff: u8,
    /// Fraction of pixels whose channels all lie within the tolerance.
    pub fraction_within: f64,
    pub pixels_outside: usize,
}

impl RgbaImage {
    pub fn new(width: u32, height: u32) -> RgbaImage {
        RgbaImage {
            width,
            height,
            pixels: vec![0; (width * height) as usize],
        }
    }

    /// Bytes in R, G, B, A order for PNG writers.
    pub fn to_rgba_bytes(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| p.to_le_bytes()).collect()
    }

    /// Writes the image as an 8-bit RGBA PNG.
    pub fn write_png(&self, out: impl std::io::Write) -> Result<(), png::EncodingError> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&self.to_rgba_bytes())?;
        writer.finish()
    }

    /// `self` on the left and `right` (of the same height) on the right.
    pub fn side_by_side(&self, right: &RgbaImage) -> RgbaImage {
        let (lw, rw) = (self.width as usize, right.width as usize);
        let mut out = RgbaImage::new(self.width + right.width, self.height);
        for y in 0..self.height.min(right.height) as usize {
            let dst = &mut out.pixels[y * (lw + rw)..(y + 1) * (lw + rw)];
            dst[..lw].copy_from_slice(&self.pixels[y * lw..(y + 1) * lw]);
            dst[lw..].copy_from_slice(&right.pixels[y * rw..(y + 1) * rw]);
        }
        out
    }

    pub fn compare(&self, other: &RgbaImage, tolerance: u8) -> ImageDiff {
        self.compare_where(other, &vec![true; self.pixels.len()], tolerance)
    }

    /// Like [`RgbaImage::compare`], but only over the pixels where `mask` is true (for
    /// example where both images show the surface). `fraction_within` is 1.0 for an empty mask.
    pub fn compare_where(&self, other: &RgbaImage, mask: &[bool], tolerance: u8) -> ImageDiff {
        assert_eq!((self.width, self.height), (other.width, other.height));
        assert_eq!(
            mask.len(),
            self.pixels.len(),
            "mask size differs from the image"
        );
        let mut max = 0u8;
        let mut outside = 0;
        let mut considered = 0usize;
        for ((a, b), _) in self
            .pixels
            .iter()
            .zip(&other.pixels)
            .zip(mask)
            .filter(|(_, &m)| m)
        {
            considered += 1;
            let d = channel_diff(*a, *b);
            max = max.max(d);
            if d > tolerance {
                outside += 1;
            }
        }
        ImageDiff {
            max_channel_diff: max,
            fraction_within: 1.0 - outside as f64 / considered.max(1) as f64,
            pixels_outside: outside,
        }
    }

    /// Per-pixel difference image (each channel's absolute difference, scaled ×8 to be seen).
    pub fn diff_image(&self, other: &RgbaImage) -> RgbaImage {
        let pixels = self
            .pixels
            .iter()
            .zip(&other.pixels)
            .map(|(a, b)| {
                let (a, b) = (a.to_le_bytes(), b.to_le_bytes());
                let c = [0, 1, 2].map(|i| (a[i].abs_diff(b[i]) as u32 * 8).min(255));
                c[0] | (c[1] << 8) | (c[2] << 16) | (255 << 24)
            })
            .collect();
        RgbaImage {
            width: self.width,
            height: self.height,
            pixels,
        }
    }
}

/// Which pixels differ from `background`, i.e. show something.
pub fn coverage_of(image: &RgbaImage, background: u32) -> Vec<bool> {
    image.pixels.iter().map(|&p| p != background).collect()
}

/// Intersection over union of two coverage masks of the same size; 1.0 when both are empty.
pub fn silhouette_iou(a: &[bool], b: &[bool]) -> f64 {
    assert_eq!(a.len(), b.len(), "coverage masks differ in size");
    let (mut both, mut either) = (0usize, 0usize);
    for (&x, &y) in a.iter().zip(b) {
        both += usize::from(x && y);
        either += usize::from(x || y);
    }
    if either == 0 {
        1.0
    } else {
        both as f64 / either as f64
    }
}

fn channel_diff(a: u32, b: u32) -> u8 {
    let (a, b) = (a.to_le_bytes(), b.to_le_bytes());
    (0..4).map(|i| a[i].abs_diff(b[i])).max().unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_counts_pixels_outside_tolerance() {
        let mut a = RgbaImage::new(2, 2);
        let mut b = a.clone();
        a.pixels[0] = 10;
        b.pixels[0] = 13;
        b.pixels[3] = 1 << 16;
        let d = a.compare(&b, 2);
        assert_eq!(d.max_channel_diff, 3);
        assert_eq!(d.pixels_outside, 1);
        assert!((d.fraction_within - 0.75).abs() < 1e-12);
    }

    #[test]
    fn masked_compare_coverage_and_iou() {
        let mut a = RgbaImage::new(2, 2);
        let mut b = a.clone();
        a.pixels[0] = 10;
        b.pixels[0] = 30;
        b.pixels[3] = 7;
        let d = a.compare_where(&b, &[false, true, true, true], 2);
        assert_eq!((d.max_channel_diff, d.pixels_outside), (7, 1));
        assert!((d.fraction_within - 2.0 / 3.0).abs() < 1e-12);
        let none = a.compare_where(&b, &[false; 4], 0);
        assert_eq!((none.pixels_outside, none.fraction_within), (0, 1.0));

        assert_eq!(coverage_of(&b, 0), vec![true, false, false, true]);
        let (x, y) = ([true, true, false, false], [false, true, true, false]);
        assert!((silhouette_iou(&x, &y) - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(silhouette_iou(&[false; 3], &[false; 3]), 1.0);
        assert_eq!(silhouette_iou(&x, &x), 1.0);
    }
}
