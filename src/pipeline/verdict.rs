//! The verdict on a wrap: one state, the badge's words and one sentence on what is wrong and what
//! to try, decided here from the certificate and what the run reported. The CLI prints it and the
//! page shows it; neither decides anything of its own.

use crate::flow::{ColourMap, StartedOver};
use crate::metrics::certificate::Certificate;
use crate::metrics::faithful::Faithfulness;
use serde::{Deserialize, Serialize};

/// What a result is, most severe first is `Invalid`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub enum VerdictState {
    /// Certified (closed, manifold, oriented, finite, no intersecting faces), the target's own
    /// topology where it has one, and no part of the target left outside.
    Valid,
    /// Certified, with the target's topology, but not faithful to the data: a membrane of the
    /// surface is left in empty space between parts of it (an opening of the data spanned is
    /// not this).
    Unfaithful,
    /// Certified, but unlike the target: another genus or part count, or a part of it outside.
    Warning,
    /// Not certified, or the run stopped before its rule said so.
    Invalid,
}

/// The verdict on one result (keys are a stable interface: `verdict` in `lsw wrap`'s output and
/// the app's result message).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
pub struct Verdict {
    pub state: VerdictState,
    /// The mesh is certified and the run was not stopped: it may be written and exported under
    /// its plain name (a `Warning` result is certified).
    pub certified: bool,
    /// The badge's parts, most important first ("✓ valid", "closed", …, "max dist 0.012").
    pub badge: Vec<String>,
    /// The status line's lead for a finished run ("Done", "Not valid", …).
    pub headline: String,
    /// One sentence: what is wrong (or right) and what to try.
    pub explanation: String,
    /// What the certificate shows beside validity, in words (see [`Certificate::warnings`]).
    pub warnings: Vec<String>,
    /// What the run left out or did again, in words ("3 stray points left out", …).
    pub notes: Vec<String>,
    /// The colour map that shows where the result is off, for the page to switch to: the
    /// flagged vertices of an unfaithful one; `None` where there is nothing to point at.
    #[serde(default)]
    pub highlight: Option<ColourMap>,
}

/// What a run left out of the target before wrapping it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LeftOut {
    /// A cloud's stray points (see `tuning.field.outlier_spacings`).
    pub strays: usize,
    /// A mesh's small closed parts floating apart (see `geometry::specks`).
    pub specks: usize,
}

impl Verdict {
    /// The verdict on `c`, for a run that stopped early with `stop` (if it did), passed the
    /// target again as `again` said (if it did) and left out `left_out`.
    pub fn of(
        c: &Certificate,
        stop: Option<&str>,
        again: Option<&StartedOver>,
        left_out: LeftOut,
    ) -> Verdict {
        let certified = c.valid && stop.is_none();
        let unlike = topology_differs(c) || c.target_part_outside;
        let state = match (certified, unlike) {
            (false, _) => VerdictState::Invalid,
            (true, true) => VerdictState::Warning,
            (true, false) if membrane(c).is_some() => VerdictState::Unfaithful,
            (true, false) => VerdictState::Valid,
        };
        let headline = match state {
            VerdictState::Invalid if stop.is_some() => "Stopped early",
            VerdictState::Invalid => "Not valid",
            VerdictState::Warning if topology_differs(c) => "Done, but not the target's topology",
            VerdictState::Warning => "Done, but part of the target lies outside the wrap",
            VerdictState::Unfaithful => "Done, but not faithful: part of it spans empty space",
            VerdictState::Valid => "Done",
        };
        let mut notes = left_out_notes(left_out);
        notes.extend(again.map(second_pass_note));
        notes.extend(c.faithfulness.as_ref().map_or(vec![], faithfulness_notes));
        Verdict {
            state,
            certified,
            badge: badge(c, certified),
            headline: headline.to_owned(),
            explanation: explain(c, stop, again),
            warnings: c.warnings(),
            notes,
            highlight: (state == VerdictState::Unfaithful).then_some(ColourMap::Flagged),
        }
    }
}

/// The share of the wrap's area in membranes left in empty space, where it is
/// [`MEMBRANE_SHARE`] or more.
fn membrane(c: &Certificate) -> Option<f64> {
    let f = c.faithfulness.as_ref()?;
    (f.membrane_share >= MEMBRANE_SHARE).then_some(f.membrane_share)
}

/// Whether the wrap's genus or part count differs from that of a closed one-part target.
fn topology_differs(c: &Certificate) -> bool {
    c.target_genus.is_some() && (c.target_genus != c.genus || c.target_components != c.components)
}

/// The badge's parts.
fn badge(c: &Certificate, certified: bool) -> Vec<String> {
    let yes_no = |b: bool, yes: &str, no: &str| if b { yes } else { no }.to_owned();
    let mut parts = vec![
        yes_no(certified, "✓ valid", "✗ not valid"),
        yes_no(c.closed, "closed", "open"),
        yes_no(c.manifold, "manifold", "non-manifold"),
        c.genus.map_or("genus ?".into(), |g| format!("genus {g}")),
        format!("{} SI", c.self_intersections),
    ];
    if topology_differs(c) {
        parts.push(format!(
            "⚠ target: genus {}, {} part(s)",
            num_or(c.target_genus),
            num_or(c.target_components)
        ));
    }
    if c.target_part_outside {
        parts.push(format!(
            "⚠ {} target points outside",
            num_or(c.target_points_outside)
        ));
    }
    if let Some(share) = membrane(c) {
        parts.push(format!("⚠ {:.1} % spans empty space", 100.0 * share));
    }
    if let Some(d) = c.distance_max {
        parts.push(format!("max dist {}", significant(d, 3)));
    }
    parts
}

/// One sentence on what is wrong with a result and what to try.
fn explain(c: &Certificate, stop: Option<&str>, again: Option<&StartedOver>) -> String {
    const VALID: &str = "Closed, manifold, no intersecting faces";
    if let Some(why) = stop {
        return format!("Stopped early ({why}). Try a smaller time step τ.");
    }
    if c.valid && topology_differs(c) {
        return format!(
            "{VALID}, but the target has genus {} in {} part(s) and this wrap genus {} in {}. Try \
             the other start surface or a finer grid.",
            num_or(c.target_genus),
            num_or(c.target_components),
            num_or(c.genus),
            num_or(c.components)
        );
    }
    if c.valid && c.target_part_outside {
        return format!("{VALID}, but {}", outside_sentence(c, again));
    }
    if let (true, Some(share)) = (c.valid, membrane(c)) {
        return format!(
            "{VALID}, but {:.1} % of its area lies {} or more local spacings from the data, in \
             membranes across empty space between parts of it (colour: off the data or \
             folded). Try Close gaps up to a smaller size, or a finer Detail.",
            100.0 * share,
            crate::metrics::faithful::FAR_SPACINGS
        );
    }
    if c.valid {
        return "Closed, manifold, oriented, no intersecting faces.".into();
    }
    if !c.finite {
        return "Has non-finite coordinates. Try a smaller time step τ.".into();
    }
    if !c.closed {
        return "Not closed. Report the share link: this is a bug.".into();
    }
    if !c.manifold || !c.oriented {
        return "Not manifold or not oriented. Report the share link: this is a bug.".into();
    }
    format!(
        "{} pairs of faces intersect. Try the other start surface or a finer grid.",
        c.self_intersections
    )
}

/// The rest of the sentence on a certified wrap that leaves part of the target outside.
fn outside_sentence(c: &Certificate, again: Option<&StartedOver>) -> String {
    let (out, checked) = (
        num_or(c.target_points_outside),
        num_or(c.target_points_checked),
    );
    let lead = format!("{out} of {checked} target points checked lie outside the wrap");
    let Some(s) = again else {
        return format!(
            "{lead}: a thin part was cut off. Try the other start surface or a finer grid; for \
             an open sheet (a single-layer scan), the obstacle preset."
        );
    };
    if !first_kept_over_fewer_outside(s) {
        return format!(
            "{lead}, also after a second pass without full-wrap's push ({} → {}): a thin part \
             or an open rim was cut off. Try a finer grid (Detail) or the other start surface.",
            s.outside_before, s.outside_after
        );
    }
    let later: Vec<i64> = [s.genus_after, s.third.and_then(|t| t.genus)]
        .into_iter()
        .flatten()
        .collect();
    let why = match s.genus_before {
        Some(first) if later.iter().any(|&g| g < first) => format!(
            "closed a hole the first had opened (genus {first}, theirs {})",
            later
                .iter()
                .map(i64::to_string)
                .collect::<Vec<_>>()
                .join(" and ")
        ),
        _ => {
            let far = s.third.map_or(s.far_after, |t| t.far.min(s.far_after));
            format!(
                "ended farther off the data ({} against {})",
                significant(far, 2),
                significant(s.far_before, 2)
            )
        }
    };
    let passes = match s.third {
        Some(_) => "the later passes",
        None => "a second pass",
    };
    format!(
        "{lead}, up to {} out (an open rim's edge or a thin part cut off); {passes} that kept \
         them {why}, so the first is shown. Try a finer grid (Detail) or the other start \
         surface.",
        significant(s.miss_before, 2)
    )
}

/// Whether the first pass is shown although a later one left fewer points outside.
fn first_kept_over_fewer_outside(s: &StartedOver) -> bool {
    !s.kept && !s.third.is_some_and(|t| t.kept) && s.outside_after < s.outside_before
}

/// "3 stray points left out", "1 small loose part left out".
fn left_out_notes(l: LeftOut) -> Vec<String> {
    let plural = |n: usize, one: &str, many: &str| match n {
        1 => format!("1 {one} left out"),
        _ => format!("{n} {many} left out"),
    };
    let mut notes = Vec::new();
    if l.strays > 0 {
        notes.push(plural(l.strays, "stray point", "stray points"));
    }
    if l.specks > 0 {
        notes.push(plural(l.specks, "small loose part", "small loose parts"));
    }
    notes
}

/// A share of vertices far from the data above which the verdict says so: a sampling's own gaps
/// leave fewer (see docs/decisions/0026-faithfulness-notes.md).
pub const FAR_NOTE_SHARE: f64 = 0.02;

/// A share of folded edges above which the verdict says so.
pub const FOLD_NOTE_SHARE: f64 = 0.001;

/// A share of the wrap's area in membranes left in empty space at which a result is not faithful (see
/// docs/decisions/0028-membranes.md).
pub const MEMBRANE_SHARE: f64 = 0.01;

/// What the faithfulness measurements show that a user should look at: regions far from the data,
/// folds. Notes, not warnings: a far region may be an opening of the data the wrap had to span.
fn faithfulness_notes(f: &Faithfulness) -> Vec<String> {
    let mut notes = Vec::new();
    if f.far_share >= FAR_NOTE_SHARE {
        notes.push(format!(
            "{} vertices ({:.1} %) lie {} or more local spacings from the data: {} opening(s) of \
             the data spanned, {} membrane(s) left in empty space",
            f.far_vertices,
            100.0 * f.far_share,
            crate::metrics::faithful::FAR_SPACINGS,
            f.openings,
            f.membranes
        ));
    }
    if f.fold_share >= FOLD_NOTE_SHARE {
        notes.push(format!(
            "{} edges fold over ({:.2} %): their faces turn by more than a right angle where the \
             data does not",
            f.folds,
            100.0 * f.fold_share
        ));
    }
    notes
}

/// What the second pass over a cloud the first left partly outside did (and a third, where the
/// second ended far off the data).
fn second_pass_note(s: &StartedOver) -> String {
    let first = format!(
        "the first pass left {} of {} checked points outside (an open rim or gaps in the \
         sampling)",
        s.outside_before, s.checked
    );
    if let Some(t) = s.third.filter(|t| t.kept) {
        return format!(
            "wrapped three times: {first}, the second {} but ended far off the data, the third {}",
            s.outside_after, t.outside
        );
    }
    let third = match s.third {
        Some(_) => " (a third pass did no better)",
        None => "",
    };
    if s.kept {
        return format!(
            "wrapped twice: {first}, the second {}{third}",
            s.outside_after
        );
    }
    match first_kept_over_fewer_outside(s) {
        true => format!(
            "a second pass left fewer points outside but ended far off the data, so the first \
             is shown{third}"
        ),
        false => format!("a second pass left more points outside, so the first is shown{third}"),
    }
}

/// A count or "?".
fn num_or<T: std::fmt::Display>(x: Option<T>) -> String {
    x.map_or("?".into(), |v| v.to_string())
}

/// `x` with `digits` significant digits, as JavaScript's `toPrecision` writes it for the badge.
fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let exponent = crate::fmath::log10(x.abs()).floor() as i32;
    if exponent < -6 || exponent >= digits as i32 {
        return format!("{:.*e}", digits - 1, x);
    }
    let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
    format!("{x:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_regions_and_folds_are_noted_not_warned() {
        let mut c = certified();
        c.faithfulness = Some(Faithfulness {
            far_vertices: 500,
            far_share: 0.05,
            folds: 40,
            fold_share: 0.002,
            ..Default::default()
        });
        let v = Verdict::of(&c, None, None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Valid);
        assert_eq!(v.notes.len(), 2, "{:?}", v.notes);
        assert!(
            v.notes[0].starts_with("500 vertices (5.0 %)") && v.notes[1].starts_with("40 edges")
        );
        c.faithfulness = Some(Faithfulness {
            far_share: 0.01,
            fold_share: 0.0005,
            ..Default::default()
        });
        assert!(Verdict::of(&c, None, None, LeftOut::default())
            .notes
            .is_empty());
    }

    /// Far regions that span openings of the data leave a result valid; membranes over
    /// [`MEMBRANE_SHARE`] of the area make it unfaithful (amber), and the badge and sentence say so.
    #[test]
    fn membranes_in_empty_space_are_unfaithful_openings_are_not() {
        let mut c = certified();
        let far = |openings, membranes, membrane_share| Faithfulness {
            far_vertices: 900,
            far_share: 0.09,
            openings,
            membranes,
            membrane_share,
            ..Default::default()
        };
        c.faithfulness = Some(far(2, 1, 0.009));
        let v = Verdict::of(&c, None, None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Valid);
        assert_eq!(v.highlight, None);
        assert!(v.notes[0].contains("2 opening(s)"), "{:?}", v.notes);
        c.faithfulness = Some(far(0, 3, 0.04));
        let v = Verdict::of(&c, None, None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Unfaithful);
        assert_eq!(v.highlight, Some(ColourMap::Flagged));
        assert!(v.certified);
        assert!(
            v.badge.contains(&"⚠ 4.0 % spans empty space".to_owned()),
            "{:?}",
            v.badge
        );
        assert!(v.explanation.contains("membranes"), "{}", v.explanation);
        // Another genus is the stronger warning.
        c.target_genus = Some(1);
        assert_eq!(
            Verdict::of(&c, None, None, LeftOut::default()).state,
            VerdictState::Warning
        );
    }

    fn certified() -> Certificate {
        Certificate {
            valid: true,
            closed: true,
            manifold: true,
            oriented: true,
            finite: true,
            genus: Some(0),
            components: Some(1),
            euler_characteristic: Some(2),
            self_intersections: 0,
            degenerate_faces: 0,
            distance_min: Some(0.0),
            distance_max: Some(0.01234),
            faithfulness: None,
            problem: None,
            target_genus: None,
            target_components: None,
            target_points_outside: Some(0),
            target_points_checked: Some(100),
            target_part_outside: false,
        }
    }

    #[test]
    fn a_certified_wrap_like_its_target_is_valid() {
        let v = Verdict::of(&certified(), None, None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Valid);
        assert!(v.certified);
        assert_eq!(v.badge[0], "✓ valid");
        assert_eq!(v.badge.last().unwrap(), "max dist 0.0123");
        assert!(v.warnings.is_empty() && v.notes.is_empty());
    }

    #[test]
    fn another_genus_or_a_part_outside_is_a_warning_not_valid() {
        let mut c = certified();
        c.target_genus = Some(1);
        c.target_components = Some(1);
        let v = Verdict::of(&c, None, None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Warning);
        assert!(v.certified);
        assert!(v.explanation.contains("target has genus 1"));
        assert_eq!(v.warnings.len(), 1);
        let mut c = certified();
        c.target_part_outside = true;
        c.target_points_outside = Some(7);
        let v = Verdict::of(&c, None, None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Warning);
        assert!(v.badge.iter().any(|p| p == "⚠ 7 target points outside"));
    }

    #[test]
    fn a_stopped_or_uncertified_run_is_invalid() {
        let v = Verdict::of(&certified(), Some("diverged"), None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Invalid);
        assert!(!v.certified);
        assert_eq!(v.badge[0], "✗ not valid");
        assert!(v.explanation.starts_with("Stopped early (diverged)"));
        let mut c = certified();
        c.valid = false;
        c.self_intersections = 3;
        let v = Verdict::of(&c, None, None, LeftOut::default());
        assert_eq!(v.state, VerdictState::Invalid);
        assert!(v.explanation.starts_with("3 pairs of faces intersect"));
    }

    #[test]
    fn what_was_left_out_is_noted() {
        let left = LeftOut {
            strays: 1,
            specks: 3,
        };
        let v = Verdict::of(&certified(), None, None, left);
        assert_eq!(
            v.notes,
            ["1 stray point left out", "3 small loose parts left out"]
        );
    }

    fn pass() -> StartedOver {
        StartedOver {
            outside_before: 254,
            outside_after: 0,
            checked: 9999,
            iso_level_before: 0.0163,
            iso_level_after: 0.0244,
            kept: true,
            far_before: 0.0,
            far_after: 0.0,
            miss_before: 0.0,
            miss_after: 0.0,
            genus_before: None,
            genus_after: None,
            third: None,
        }
    }

    fn third(kept: bool) -> crate::flow::ThirdPass {
        crate::flow::ThirdPass {
            d2: 0.5,
            outside: 1,
            miss: 0.0,
            far: 0.03,
            genus: None,
            kept,
        }
    }

    #[test]
    fn a_second_and_third_pass_are_told() {
        let first = "the first pass left 254 of 9999 checked points outside (an open rim or gaps \
                     in the sampling)";
        assert_eq!(
            second_pass_note(&pass()),
            format!("wrapped twice: {first}, the second 0")
        );
        let worse = StartedOver {
            outside_after: 300,
            kept: false,
            ..pass()
        };
        assert_eq!(
            second_pass_note(&worse),
            "a second pass left more points outside, so the first is shown"
        );
        let three = StartedOver {
            kept: false,
            third: Some(third(true)),
            ..pass()
        };
        assert_eq!(
            second_pass_note(&three),
            format!(
                "wrapped three times: {first}, the second 0 but ended far off the data, the third 1"
            )
        );
        let no_better = StartedOver {
            third: Some(third(false)),
            ..pass()
        };
        assert_eq!(
            second_pass_note(&no_better),
            format!("wrapped twice: {first}, the second 0 (a third pass did no better)")
        );
    }

    #[test]
    fn a_part_left_outside_is_explained_with_its_passes() {
        let mut c = certified();
        c.target_part_outside = true;
        c.target_points_outside = Some(390);
        c.target_points_checked = Some(20000);
        let once = explain(&c, None, None);
        assert!(once.contains("for an open sheet (a single-layer scan), the obstacle preset"));
        let again = StartedOver {
            outside_before: 4379,
            outside_after: 390,
            checked: 20000,
            ..pass()
        };
        let text = explain(&c, None, Some(&again));
        assert!(text.contains("also after a second pass without full-wrap's push (4379 → 390)"));
        assert!(!text.contains("obstacle preset"));
        let far = StartedOver {
            outside_before: 188,
            outside_after: 7,
            checked: 16748,
            kept: false,
            far_before: 0.0292,
            far_after: 0.279,
            miss_before: 0.0494,
            third: Some(crate::flow::ThirdPass {
                far: 0.113,
                outside: 0,
                ..third(false)
            }),
            ..pass()
        };
        assert!(explain(&c, None, Some(&far)).contains(
            "up to 0.049 out (an open rim's edge or a thin part cut off); the later passes that \
             kept them ended farther off the data (0.11 against 0.029), so the first is shown"
        ));
        let hole = StartedOver {
            genus_before: Some(3),
            genus_after: Some(1),
            third: Some(crate::flow::ThirdPass {
                genus: Some(2),
                ..third(false)
            }),
            ..far
        };
        assert!(explain(&c, None, Some(&hole)).contains(
            "the later passes that kept them closed a hole the first had opened (genus 3, theirs \
             1 and 2), so the first is shown"
        ));
    }

    #[test]
    fn significant_digits_match_to_precision() {
        assert_eq!(significant(0.01234, 3), "0.0123");
        assert_eq!(significant(21.04, 3), "21.0");
        assert_eq!(significant(1234.0, 3), "1.23e3");
        assert_eq!(significant(2.5, 2), "2.5");
    }
}
