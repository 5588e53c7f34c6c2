//! The key naming one trial in plans and results files. A leaf: it imports nothing of the
//! crate, so the spec's plan and the results store share it without depending on each other.

/// The key of trial `trial` of configuration `config` on instance `instance`:
/// `instance/config/trial` (unique within an experiment: names and labels are unique).
pub fn trial_key(instance: &str, config: &str, trial: u32) -> String {
    format!("{instance}/{config}/{trial}")
}

#[cfg(test)]
mod tests {
    #[test]
    fn key_joins_instance_configuration_and_trial() {
        assert_eq!(
            super::trial_key("tuning", "AED phi=1.2", 7),
            "tuning/AED phi=1.2/7"
        );
    }
}
