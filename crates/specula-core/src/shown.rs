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

/// A number as people write it: four significant digits without an exponent between 1e-4
/// and 1e6 (`5.214`, `0.02`, `3`), otherwise in scientific notation (`1.234e-7`); `0` for
/// zero.
pub fn plain(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{}", if x == 0.0 { 0.0 } else { x });
    }
    let magnitude = x.abs();
    if !(1e-4..1e6).contains(&magnitude) {
        return format!("{x:.3e}");
    }
    let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
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
