//! The machine a run happened on, recorded in the results file.

use serde::{Deserialize, Serialize};

/// Machine description stored with results (CPU model, logical CPUs, threads used).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MachineInfo {
    /// CPU model name from /proc/cpuinfo ("unknown" elsewhere).
    pub cpu_model: String,
    /// Logical CPUs visible to the process.
    pub logical_cpus: usize,
    /// Worker threads used for trials.
    pub threads: usize,
    /// Operating system and architecture (`std::env::consts`).
    pub os: String,
    /// Host name from /proc/sys/kernel/hostname or $HOSTNAME, if known.
    pub hostname: Option<String>,
}

impl MachineInfo {
    /// Describes the current machine, running `threads` worker threads.
    pub fn current(threads: usize) -> Self {
        let cpu_model = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| cpu_model_from_cpuinfo(&s))
            .unwrap_or_else(|| "unknown".to_string());
        let hostname = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .ok()
            .map(|s| s.trim().to_string())
            .or_else(|| std::env::var("HOSTNAME").ok())
            .filter(|s| !s.is_empty());
        MachineInfo {
            cpu_model,
            logical_cpus: std::thread::available_parallelism()
                .map(|n| n.get())
                .unwrap_or(1),
            threads,
            os: format!("{}-{}", std::env::consts::OS, std::env::consts::ARCH),
            hostname,
        }
    }
}

/// The first `model name` entry of a /proc/cpuinfo text.
pub fn cpu_model_from_cpuinfo(text: &str) -> Option<String> {
    text.lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, v)| v.trim().to_string())
}

/// Seconds since the Unix epoch (0 if the clock is before it).
pub fn unix_now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_cpu_model() {
        let text = "processor\t: 0\nvendor_id\t: GenuineIntel\nmodel name\t: Intel(R) Xeon(R) CPU @ 2.20GHz\n";
        assert_eq!(
            cpu_model_from_cpuinfo(text).as_deref(),
            Some("Intel(R) Xeon(R) CPU @ 2.20GHz")
        );
        assert_eq!(cpu_model_from_cpuinfo("nothing"), None);
        assert!(MachineInfo::current(2).logical_cpus >= 1);
    }
}
