//! Golden-section search for the minimum of a function of one variable on a
//! bracket: Newton's line search at a cycle of two iterates
//! ([`super::newton`]), the contact-edge fits of the mortar interface and the
//! first touch of two surfaces all shrink their brackets here.

/// What [`golden_section`] found: the smallest value seen with its point,
/// and the last bracket (shrunk once more around the better of its two
/// interior points).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoldenSection {
    /// `(x, f(x))` with the smallest `f` evaluated (the first such point).
    pub best: (f64, f64),
    /// The last bracket `(a, b)`.
    pub bracket: (f64, f64),
}

impl GoldenSection {
    /// The middle of the last bracket.
    pub fn midpoint(&self) -> f64 {
        0.5 * (self.bracket.0 + self.bracket.1)
    }
}

/// Golden-section search of `f` on `bracket`: the two interior golden
/// points, then at most `sections` sections, each evaluating `f` once (the
/// interior point kept is the other's golden point), so `sections + 2`
/// evaluations at most. Before each section the smallest value seen is
/// passed to `done`, which ends the search where it returns true. An error of
/// `f` ends the search and is returned.
pub fn golden_section<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    bracket: (f64, f64),
    sections: usize,
    mut done: impl FnMut(f64) -> bool,
) -> Result<GoldenSection, E> {
    // The inverse golden ratio: each section keeps this fraction.
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = bracket;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    let mut best = (c, f64::INFINITY);
    let seen = |best: &mut (f64, f64), points: [(f64, f64); 2]| {
        for (x, v) in points {
            if v < best.1 {
                *best = (x, v);
            }
        }
    };
    for _ in 0..sections {
        seen(&mut best, [(c, fc), (d, fd)]);
        if done(best.1) {
            break;
        }
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - g * (b - a);
            fc = f(c)?;
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + g * (b - a);
            fd = f(d)?;
        }
    }
    seen(&mut best, [(c, fc), (d, fd)]);
    let bracket = if fc < fd { (a, d) } else { (c, b) };
    Ok(GoldenSection { best, bracket })
}

/// [`golden_section`] of an infallible `f`, every one of `sections` taken.
pub fn golden_search(
    mut f: impl FnMut(f64) -> f64,
    bracket: (f64, f64),
    sections: usize,
) -> GoldenSection {
    let infallible = |x| Ok::<_, std::convert::Infallible>(f(x));
    match golden_section(infallible, bracket, sections, |_| false) {
        Ok(found) => found,
        Err(never) => match never {},
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::convert::Infallible;

    /// The inverse golden ratio.
    fn g() -> f64 {
        0.5 * (5f64.sqrt() - 1.0)
    }

    /// A smooth minimum is bracketed to a few ulps of the bracket's width
    /// after enough sections, with one evaluation per section; `done` ends
    /// the search early; an error of `f` is returned as it is.
    #[test]
    fn sections_shrink_the_bracket_once_per_evaluation() {
        let mut calls = 0;
        let f = |x: f64| -> Result<f64, Infallible> {
            calls += 1;
            Ok((x - 0.3).powi(2))
        };
        let s = golden_section(f, (0.0, 1.0), 60, |_| false).unwrap();
        assert_eq!(calls, 62);
        assert!((s.midpoint() - 0.3).abs() < 1e-8, "{s:?}");
        assert!((s.best.0 - 0.3).abs() < 1e-8 && s.best.1 < 1e-16, "{s:?}");
        let width = s.bracket.1 - s.bracket.0;
        assert!(width > 0.0 && width < 2.0 * g().powi(61), "{width}");
        // Stopping at the first value below 1e-2.
        let mut calls = 0;
        let s = golden_section(
            |x: f64| -> Result<f64, Infallible> {
                calls += 1;
                Ok((x - 0.3).powi(2))
            },
            (0.0, 1.0),
            60,
            |m| m < 1e-2,
        )
        .unwrap();
        assert!(s.best.1 < 1e-2 && calls < 10, "{s:?} after {calls}");
        // An error on the third evaluation.
        let mut calls = 0;
        let e = golden_section(
            |x: f64| {
                calls += 1;
                if calls == 3 { Err("refused") } else { Ok(x) }
            },
            (0.0, 1.0),
            10,
            |_| false,
        );
        assert_eq!(e, Err("refused"));
    }

    /// With no section, the best of the two golden points and the bracket
    /// kept around it.
    #[test]
    fn no_section_compares_the_two_golden_points() {
        let s = golden_section(Ok::<_, Infallible>, (0.0, 1.0), 0, |_| false).unwrap();
        let g = g();
        assert_eq!(s.best, (1.0 - g, 1.0 - g));
        assert_eq!(s.bracket, (0.0, g));
    }
}
