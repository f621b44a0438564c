//! Image error against a reference frame: what the error budget trades.

/// How far an image is from a reference of the same size.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageError {
    /// Mean absolute difference over every pixel's R, G and B, in 8-bit steps (0..=255).
    pub mean_abs: f64,
    /// Share of pixels (0..=1) with a channel off by more than 8/255.
    pub share_over_8: f64,
}

/// Channel difference above which a pixel counts as off.
pub const OFF_THRESHOLD: u8 = 8;

/// The error of RGBA8 image `image` against `reference` (alpha ignored), or `None` when their
/// sizes differ.
pub fn image_error(image: &[u8], reference: &[u8]) -> Option<ImageError> {
    if image.len() != reference.len() || !image.len().is_multiple_of(4) || image.is_empty() {
        return None;
    }
    let mut sum = 0u64;
    let mut off = 0u64;
    for (a, b) in image.chunks_exact(4).zip(reference.chunks_exact(4)) {
        let d: [u8; 3] = std::array::from_fn(|i| a[i].abs_diff(b[i]));
        sum += d.iter().map(|&x| u64::from(x)).sum::<u64>();
        off += u64::from(d.iter().any(|&x| x > OFF_THRESHOLD));
    }
    let pixels = (image.len() / 4) as f64;
    Some(ImageError {
        mean_abs: sum as f64 / (pixels * 3.0),
        share_over_8: off as f64 / pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_mean_and_share() {
        let reference = [10, 10, 10, 255, 0, 0, 0, 255];
        assert_eq!(
            image_error(&reference, &reference),
            Some(ImageError::default())
        );
        // Pixel 0 off by 9 in red (counts), pixel 1 off by 8 in blue (does not).
        let image = [19, 10, 10, 0, 0, 0, 8, 0];
        let e = image_error(&image, &reference).unwrap();
        assert!((e.mean_abs - 17.0 / 6.0).abs() < 1e-12);
        assert!((e.share_over_8 - 0.5).abs() < 1e-12);
        assert_eq!(image_error(&image[..4], &reference), None);
    }
}
