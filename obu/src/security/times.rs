//! The time rules of a [`SecurityProfile`]: whether a signed message's generation and expiry
//! times make it relevant now. Pure: every time is a `Time64` (TAI microseconds since 2004).

use super::{Rejection, SecurityProfile};

/// Checks a message generated at `generated` (if it says) and expiring at `expiry` (if it
/// says) against `now` by `profile`, in this order: the required times are there, the
/// generation time is before the expiry time and their distance is at most the longest
/// lifetime, the generation time is at most the future tolerance ahead, and the message is
/// still relevant: until its expiry time (plus the future tolerance), or, without one, for
/// the past window after its generation. Returns when it stops being relevant.
///
/// # Errors
///
/// The [`Rejection`] of the first rule that fails.
pub(crate) fn check(
    profile: &SecurityProfile,
    generated: Option<u64>,
    expiry: Option<u64>,
    now: u64,
) -> Result<u64, Rejection> {
    let tolerance = u64::from(profile.future_tolerance_ms) * 1000;
    if generated.is_none() && (profile.require_generation_time || expiry.is_none()) {
        return Err(Rejection::NoGenerationTime);
    }
    if expiry.is_none() && profile.require_expiry_time {
        return Err(Rejection::NoExpiryTime);
    }
    if let (Some(generated), Some(expiry)) = (generated, expiry) {
        if generated >= expiry {
            return Err(Rejection::ExpiryBeforeGeneration);
        }
        if expiry - generated > profile.max_lifetime_ms.saturating_mul(1000) {
            return Err(Rejection::LifetimeTooLong);
        }
    }
    if generated.is_some_and(|g| g > now.saturating_add(tolerance)) {
        return Err(Rejection::GenerationTimeFuture);
    }
    let relevant_until = match (expiry, generated) {
        (Some(expiry), _) => expiry.saturating_add(tolerance),
        (None, Some(generated)) => {
            generated.saturating_add(u64::from(profile.past_window_ms) * 1000)
        }
        (None, None) => return Err(Rejection::NoGenerationTime),
    };
    if now > relevant_until {
        return Err(if expiry.is_some() {
            Rejection::MessageExpired
        } else {
            Rejection::GenerationTimeOld
        });
    }
    Ok(relevant_until)
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: u64 = 1_000_000;
    const DAY: u64 = 24 * 3600 * S;
    const NOW: u64 = 700_000_000 * S;

    fn tim() -> SecurityProfile {
        SecurityProfile::TIM
    }

    #[test]
    fn signed_per_transmission_is_relevant_for_the_past_window() {
        assert_eq!(check(&tim(), Some(NOW - 29 * S), None, NOW), Ok(NOW + S));
        assert_eq!(
            check(&tim(), Some(NOW - 31 * S), None, NOW),
            Err(Rejection::GenerationTimeOld)
        );
        assert_eq!(
            check(&tim(), Some(NOW + 4 * S), None, NOW),
            Ok(NOW + 34 * S)
        );
        assert_eq!(
            check(&tim(), Some(NOW + 6 * S), None, NOW),
            Err(Rejection::GenerationTimeFuture)
        );
    }

    #[test]
    fn signed_once_with_an_expiry_is_relevant_until_it() {
        // Signed two hours ago for a day: the deposited-TIM pattern.
        let generated = NOW - 2 * 3600 * S;
        let expiry = generated + DAY;
        assert_eq!(
            check(&tim(), Some(generated), Some(expiry), NOW),
            Ok(expiry + 5 * S)
        );
        assert_eq!(
            check(&tim(), Some(generated), Some(NOW - 6 * S), NOW),
            Err(Rejection::MessageExpired)
        );
        assert!(check(&tim(), Some(generated), Some(NOW - 4 * S), NOW).is_ok());
    }

    #[test]
    fn impossible_or_overlong_lifetimes_are_refused() {
        assert_eq!(
            check(&tim(), Some(NOW), Some(NOW), NOW),
            Err(Rejection::ExpiryBeforeGeneration)
        );
        assert_eq!(
            check(&tim(), Some(NOW), Some(NOW + 7 * DAY + 1), NOW),
            Err(Rejection::LifetimeTooLong)
        );
        assert!(check(&tim(), Some(NOW), Some(NOW + 7 * DAY), NOW).is_ok());
    }

    #[test]
    fn required_times_are_required() {
        assert_eq!(
            check(&tim(), None, Some(NOW + S), NOW),
            Err(Rejection::NoGenerationTime)
        );
        let lenient = SecurityProfile {
            require_generation_time: false,
            ..tim()
        };
        assert_eq!(check(&lenient, None, Some(NOW + S), NOW), Ok(NOW + 6 * S));
        assert_eq!(
            check(&lenient, None, None, NOW),
            Err(Rejection::NoGenerationTime)
        );
        let strict = SecurityProfile {
            require_expiry_time: true,
            ..tim()
        };
        assert_eq!(
            check(&strict, Some(NOW), None, NOW),
            Err(Rejection::NoExpiryTime)
        );
    }
}
