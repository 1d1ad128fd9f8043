//! Numbers as text: the shortest decimal that reads back to the same `f64`,
//! in exponent form when plain digits would be long (`0.1`, `1e-12`, `1e20`).
//! One formatter for everything that prints or writes numbers (`print`, CSV,
//! BVH, motion summaries), so a value looks the same wherever it appears.

use std::fmt;

/// `format!("{}", Shortest(x))` is the shortest round-trip text of `x`
/// (`nan`, `inf`, `-inf`, `-0` for the special values). Writing through
/// `Display` lets bulk writers (CSV, BVH) format without a `String` per number.
#[derive(Clone, Copy, Debug)]
pub struct Shortest(pub f64);

impl fmt::Display for Shortest {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x.is_nan() {
            return f.write_str("nan");
        }
        if x.is_infinite() {
            return f.write_str(if x > 0.0 { "inf" } else { "-inf" });
        }
        // Rust's `{}` prints the shortest round-trip digits but never uses an
        // exponent (1e-12 → 0.000000000001, 1e300 → 1 followed by 300 digits);
        // `{:e}` always does. Pick by magnitude; zero is plain (`0`, `-0`).
        let ax = x.abs();
        if ax == 0.0 || (1e-5..1e16).contains(&ax) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

/// The shortest decimal that reads back to the same `f64` (`0.1`, `1e-12`, `3`).
pub fn format_number(x: f64) -> String {
    Shortest(x).to_string()
}

/// `x` rounded to `digits` significant digits (at least 1, at most 17).
pub fn round_significant(x: f64, digits: usize) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    // through decimal text: exact decimal rounding, no 10^k scaling error
    format!("{:.*e}", digits.clamp(1, 17) - 1, x)
        .parse()
        .unwrap_or(x)
}

/// Summaries' numbers (spans, reports): 6 significant digits, written as
/// [`Shortest`] writes them, so a span read from a 30 Hz file shows as
/// `[0, 6.46667]`, not `[0, 6.466660200000001]` (the exact value stays with
/// `repr`, `print` and the files).
#[derive(Clone, Copy, Debug)]
pub struct Rounded(pub f64);

/// Significant digits of [`Rounded`]: µs on spans up to 10 s, ms to 1000 s.
pub const SUMMARY_DIGITS: usize = 6;

impl fmt::Display for Rounded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        Shortest(round_significant(self.0, SUMMARY_DIGITS)).fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_round_trip_with_exponent_for_extremes() {
        for (x, s) in [
            (0.1, "0.1"),
            (1e-12, "1e-12"),
            (1e-300, "1e-300"),
            (-2.44e-17, "-2.44e-17"),
            (3.0, "3"),
            (-2.5, "-2.5"),
            (1e20, "1e20"),
            (123456.0, "123456"),
            (123456789012.0, "123456789012"),
            (0.00001, "0.00001"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (5e-324, "5e-324"),
            (f64::MAX, "1.7976931348623157e308"),
            (0.1 + 0.2, "0.30000000000000004"),
        ] {
            assert_eq!(format_number(x), s);
            assert_eq!(s.parse::<f64>().ok(), Some(x), "{s} reads back");
        }
    }

    #[test]
    fn rounded_keeps_six_significant_digits() {
        for (x, s) in [
            (6.466660200000001, "6.46666"),
            (2.0, "2"),
            (0.30000000000000004, "0.3"),
            (1234567.0, "1234570"),
            (-0.000123456789, "-0.000123457"),
            (0.0, "0"),
        ] {
            assert_eq!(Rounded(x).to_string(), s);
        }
        assert_eq!(round_significant(6.466660200000001, 3), 6.47);
        assert_eq!(round_significant(-1234.5, 2), -1200.0);
        assert!(round_significant(f64::NAN, 3).is_nan());
    }

    #[test]
    fn special_values() {
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(-0.0), "-0");
        assert!(
            format_number(-0.0)
                .parse::<f64>()
                .unwrap()
                .is_sign_negative()
        );
        assert_eq!(format_number(f64::NAN), "nan");
        assert_eq!(format_number(f64::INFINITY), "inf");
        assert_eq!(format_number(f64::NEG_INFINITY), "-inf");
    }
}
