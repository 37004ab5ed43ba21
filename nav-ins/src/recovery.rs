//! A recovery from a lock-out into divergence, as the navigator records it
//! ([`nav_runtime::recovery`]; docs/lockout.md, "Recovery").

/// One recovery: the filter inflated the covariance of the states `sensor`
/// observes after its readings had been refused for `refused_for_s` while
/// plausible and agreeing with one another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Recovery {
    /// The log sensor (`dvl`, `depth`, `heading`, `usbl`, ...).
    pub sensor: &'static str,
    /// Time of the reading after which the filter recovered (s, log clock):
    /// with a rollback, the second reading of the run that proved the
    /// filter wrong.
    pub t_s: f64,
    /// How long the sensor's readings had been refused (s).
    pub refused_for_s: f64,
    /// Time of the reading that completed that proof (s, log clock): `t_s`
    /// itself unless the filter was taken back before `t_s`
    /// (docs/lockout.md, "Rollback").
    pub detected_s: f64,
}
