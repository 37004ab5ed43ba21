//! A recovery from a lock-out into divergence, as the navigator records it
//! ([`nav_runtime::recovery`]; docs/lockout.md, "Recovery").

/// One recovery: the filter inflated the covariance of the states `sensor`
/// observes after its readings had been refused for `refused_for_s` while
/// plausible and agreeing with one another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Recovery {
    /// The log sensor (`dvl`, `depth`, `heading`, `usbl`, ...).
    pub sensor: &'static str,
    /// Time of the reading after which the filter recovered (s, log clock).
    pub t_s: f64,
    /// How long the sensor's readings had been refused (s).
    pub refused_for_s: f64,
}
