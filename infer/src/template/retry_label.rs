//! How a plan's retries read in a summary, one wording for `plan`, `eval
//! learned`'s planner names and the pipeline's report.

use super::TemplateSettings;
use core::fmt;

/// [`TemplateSettings`]' retries in words ([`TemplateSettings::retry_label`]):
/// "a miss retried up to 3 × with 9600 evaluations, retry 3 in 1 dig
/// more"; empty where there is no retry.
#[derive(Debug)]
pub struct RetryLabel<'s>(&'s TemplateSettings);

impl fmt::Display for RetryLabel<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.0;
        match (s.retry, s.retries) {
            (0, _) => return Ok(()),
            (r, 1) => write!(f, "a miss retried with {r} evaluations")?,
            (r, n) => write!(f, "a miss retried up to {n} × with {r} evaluations")?,
        }
        let more = s.retry_more_digs.iter().take(s.retries).enumerate();
        for (i, &m) in more.filter(|(_, m)| **m > 0) {
            let digs = if m == 1 { "dig" } else { "digs" };
            write!(f, ", retry {} in {m} {digs} more", i + 1)?;
        }
        Ok(())
    }
}

impl TemplateSettings {
    /// The retries in words, for a summary.
    pub fn retry_label(&self) -> RetryLabel<'_> {
        RetryLabel(self)
    }
}
