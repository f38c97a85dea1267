//! Numbers in messages as people read them: a value from a file or a device may be 1e300,
//! which `{}` prints with 300 digits.

/// `x` with at most 6 decimals when its magnitude is in `[1e-4, 1e6)` (or it is 0), in
/// exponent form otherwise (`1e300`, `-3.5e-9`); `inf`, `-inf` and `NaN` as themselves.
pub fn shown(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) {
        let text = format!("{x:.6}");
        return text.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    format!("{x:e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_show_with_few_digits() {
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(-1e300), "-1e300");
        assert_eq!(shown(4095.0), "4095");
        assert_eq!(shown(0.25), "0.25");
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(-3.5e-9), "-3.5e-9");
        assert_eq!(shown(f64::INFINITY), "inf");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(shown(1234.5678912), "1234.567891");
        assert_eq!(shown(360000.0), "360000");
    }
}
