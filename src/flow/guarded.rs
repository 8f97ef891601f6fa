//! The one guarded edit: apply an edit, check the result exactly, and where the check fails
//! freeze the region it blames and try again; out of tries, roll back. The contact guard, the
//! remesh of a step and of a fit pass, the fit's crease snap and its sliver tidy all run through
//! [`guarded_edit`], each with its own edit, check and roll-back.
//!
//! The frozen region is a mask over the vertices of the surface the tries start from: the check
//! grows it, the next try leaves it alone. Whatever the edit and the check need besides (the
//! mesh, its start, timings) travels in a context both borrow in turn.

/// What the check makes of one try of the edit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Verdict {
    /// The try passed: it stands.
    Clean,
    /// The try failed and the check froze the region it blames: try again.
    Retry,
    /// The try failed and nothing can be frozen to help: roll back now.
    GiveUp,
}

impl Verdict {
    /// Clean when `clean`, else give up: the check of an edit that is not retried.
    pub(crate) fn clean_if(clean: bool) -> Self {
        match clean {
            true => Verdict::Clean,
            false => Verdict::GiveUp,
        }
    }
}

/// How many tries a guarded edit gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct GuardPolicy {
    /// Checks at most, each of one try.
    pub tries: usize,
    /// The caller made the first try already: the first check comes before any edit.
    pub applied: bool,
}

impl GuardPolicy {
    /// One try, made by the edit: it stands or is rolled back.
    pub(crate) const ONCE: Self = Self {
        tries: 1,
        applied: false,
    };
}

/// How a guarded edit ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct GuardOutcome {
    /// A try passed its check (else the edit was rolled back).
    pub clean: bool,
    /// Checks run.
    pub checks: usize,
}

/// Runs `edit` and `check` on `cx` in turn until a try is [`Verdict::Clean`], at most
/// `policy.tries` checks. `edit` makes one try leaving the `frozen` vertices alone and answers
/// false when it could not (the edit gave out: no check, roll back); `check` judges the try and
/// on failure grows `frozen`. Without a clean try `roll_back` runs. An edit's error ends it at
/// once, with nothing rolled back.
pub(crate) fn guarded_edit<C: ?Sized, E>(
    cx: &mut C,
    frozen: &mut [bool],
    policy: GuardPolicy,
    mut edit: impl FnMut(&mut C, &[bool]) -> Result<bool, E>,
    mut check: impl FnMut(&mut C, &mut [bool]) -> Verdict,
    roll_back: impl FnOnce(&mut C),
) -> Result<GuardOutcome, E> {
    let mut checks = 0;
    for k in 0..policy.tries {
        if (k > 0 || !policy.applied) && !edit(cx, frozen)? {
            break;
        }
        checks += 1;
        match check(cx, frozen) {
            Verdict::Clean => {
                return Ok(GuardOutcome {
                    clean: true,
                    checks,
                })
            }
            Verdict::Retry => {}
            Verdict::GiveUp => break,
        }
    }
    roll_back(cx);
    Ok(GuardOutcome {
        clean: false,
        checks,
    })
}

/// [`guarded_edit`] with an edit that cannot fail.
pub(crate) fn guarded<C: ?Sized>(
    cx: &mut C,
    frozen: &mut [bool],
    policy: GuardPolicy,
    mut edit: impl FnMut(&mut C, &[bool]) -> bool,
    check: impl FnMut(&mut C, &mut [bool]) -> Verdict,
    roll_back: impl FnOnce(&mut C),
) -> GuardOutcome {
    let edit = |cx: &mut C, f: &[bool]| Ok::<_, std::convert::Infallible>(edit(cx, f));
    match guarded_edit(cx, frozen, policy, edit, check, roll_back) {
        Ok(outcome) => outcome,
        Err(never) => match never {},
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A toy edit: every unfrozen entry is set; the check fails on the set entries below 2,
    /// freezing them.
    fn run(tries: usize, applied: bool) -> (Vec<u8>, GuardOutcome) {
        let mut v = if applied { vec![1u8; 4] } else { vec![0u8; 4] };
        let mut frozen = vec![false; 4];
        let policy = GuardPolicy { tries, applied };
        let out = guarded(
            &mut v,
            &mut frozen,
            policy,
            |v, frozen| {
                for (x, &f) in v.iter_mut().zip(frozen) {
                    *x = if f { 0 } else { 1 };
                }
                true
            },
            |v, frozen| {
                let bad: Vec<usize> = (0..2).filter(|&i| v[i] == 1).collect();
                bad.iter().for_each(|&i| frozen[i] = true);
                if bad.is_empty() {
                    Verdict::Clean
                } else {
                    Verdict::Retry
                }
            },
            |v| v.iter_mut().for_each(|x| *x = 9),
        );
        (v, out)
    }

    #[test]
    fn a_failed_try_is_redone_with_its_region_frozen() {
        let (v, out) = run(2, false);
        assert_eq!(v, [0, 0, 1, 1]);
        assert_eq!(
            out,
            GuardOutcome {
                clean: true,
                checks: 2
            }
        );
        let (v, out) = run(2, true);
        assert_eq!((v, out.checks), (vec![0, 0, 1, 1], 2));
    }

    #[test]
    fn out_of_tries_it_rolls_back() {
        let (v, out) = run(1, false);
        assert_eq!(v, [9; 4]);
        assert_eq!(
            out,
            GuardOutcome {
                clean: false,
                checks: 1
            }
        );
    }
}
