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
