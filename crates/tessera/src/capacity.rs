//! The rule every buffer that grows after an overflow follows: room for what was needed plus a
//! quarter, so that a count creeping up from frame to frame does not grow it every frame.

/// The capacity for `needed` items when `now` are room: unchanged where they fit, else
/// `needed` with a quarter of headroom.
pub fn grown_capacity(now: u32, needed: u32) -> u32 {
    if needed <= now {
        now
    } else {
        needed.saturating_add(needed / 4)
    }
}

#[cfg(test)]
mod tests {
    use super::grown_capacity;

    #[test]
    fn grows_by_a_quarter_only_past_the_capacity() {
        assert_eq!(grown_capacity(100, 100), 100);
        assert_eq!(grown_capacity(100, 7), 100);
        assert_eq!(grown_capacity(100, 101), 126);
        assert_eq!(grown_capacity(0, 16), 20);
        assert_eq!(grown_capacity(0, u32::MAX), u32::MAX);
    }
}
