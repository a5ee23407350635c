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

    pub fn compare(&self, other: &RgbaImage, tolerance: u8) -> ImageDiff {
        assert_eq!((self.width, self.height), (other.width, other.height));
        let mut max = 0u8;
        let mut outside = 0;
        for (a, b) in self.pixels.iter().zip(&other.pixels) {
            let d = channel_diff(*a, *b);
            max = max.max(d);
            if d > tolerance {
                outside += 1;
            }
        }
        ImageDiff {
            max_channel_diff: max,
            fraction_within: 1.0 - outside as f64 / self.pixels.len().max(1) as f64,
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
}
