//! Repeated measurements: the same scenario run more than once, and the cells whose medians
//! moved between runs by more than [`REPEAT_TOLERANCE`] flagged, so that a table is only
//! trusted where it reproduces.

use super::BenchRecord;
use std::collections::BTreeMap;

/// How far (relative to the smallest) a stage's medians may spread over the runs of a cell.
pub const REPEAT_TOLERANCE: f64 = 0.03;

/// One stage of one cell measured in several runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Spread {
    /// Scenario, technique, path, variant, dataset and image size, as a table names the cell.
    pub cell: String,
    pub stage: String,
    /// The stage's median in each run, in run order.
    pub medians_ms: Vec<f64>,
    /// (largest − smallest) / smallest.
    pub spread: f64,
}

impl Spread {
    pub fn flagged(&self) -> bool {
        self.spread > REPEAT_TOLERANCE
    }
}

/// The repeat check as lines to print: how many stages moved by more than the tolerance, then
/// each of those with its medians.
pub fn report(spreads: &[Spread]) -> Vec<String> {
    let flagged: Vec<&Spread> = spreads.iter().filter(|s| s.flagged()).collect();
    let mut lines = vec![format!(
        "repeat check: {} of {} stages moved by more than {:.0} % between runs{}",
        flagged.len(),
        spreads.len(),
        100.0 * REPEAT_TOLERANCE,
        if flagged.is_empty() { "" } else { ":" }
    )];
    for s in flagged {
        let medians: Vec<String> = s.medians_ms.iter().map(|m| format!("{m:.3}")).collect();
        lines.push(format!(
            "  {} / {}: {} ms ({:.1} %)",
            s.cell,
            s.stage,
            medians.join(", "),
            100.0 * s.spread
        ));
    }
    lines
}

fn cell_name(r: &BenchRecord) -> String {
    let variant = if r.variant.is_empty() {
        String::new()
    } else {
        format!(" [{}]", r.variant)
    };
    format!(
        "{} {} {}{variant} {} {}x{}",
        r.scenario, r.technique, r.path, r.dataset, r.width, r.height
    )
}

/// The spread of every stage of every cell that `records` (from all runs, each tagged with
/// its `repeat`) hold more than once, in the order the cells were first measured.
pub fn spreads(records: &[BenchRecord]) -> Vec<Spread> {
    let mut order: Vec<(String, String)> = Vec::new();
    let mut medians: BTreeMap<(String, String), Vec<f64>> = BTreeMap::new();
    for r in records {
        let cell = cell_name(r);
        for s in &r.stages {
            let key = (cell.clone(), s.stage.clone());
            let entry = medians.entry(key.clone()).or_insert_with(|| {
                order.push(key);
                Vec::new()
            });
            entry.push(s.median_ms);
        }
    }
    order
        .into_iter()
        .filter_map(|key| {
            let m = &medians[&key];
            if m.len() < 2 {
                return None;
            }
            let lo = m.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = m.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let spread = if lo > 0.0 { (hi - lo) / lo } else { 0.0 };
            Some(Spread {
                cell: key.0,
                stage: key.1,
                medians_ms: m.clone(),
                spread,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::StageStats;

    fn record(technique: &str, repeat: u32, stages: &[(&str, f64)]) -> BenchRecord {
        BenchRecord {
            scenario: "iso-sweep".into(),
            technique: technique.into(),
            path: "compute".into(),
            variant: String::new(),
            dataset: "head".into(),
            width: 64,
            height: 48,
            warmup: 10,
            frames: 30,
            repeat,
            stages: stages
                .iter()
                .map(|(name, ms)| StageStats::from_samples(name, &[*ms]))
                .collect(),
            counts: BTreeMap::new(),
            device: "d".into(),
            driver: "v".into(),
            unix_time_s: 0.0,
            keep_busy_ms: 0.0,
        }
    }

    #[test]
    fn cells_that_moved_more_than_three_percent_are_flagged() {
        let records = [
            record("direct", 0, &[("direct", 1.00)]),
            record("meshlets", 0, &[("extract", 2.00), ("draw", 1.0)]),
            record("direct", 1, &[("direct", 1.02)]),
            record("meshlets", 1, &[("extract", 2.10), ("draw", 1.0)]),
            record("raymarch", 1, &[("raymarch", 5.0)]),
        ];
        let s = spreads(&records);
        let names: Vec<(&str, &str, bool)> = s
            .iter()
            .map(|x| (x.cell.as_str(), x.stage.as_str(), x.flagged()))
            .collect();
        assert_eq!(
            names,
            [
                ("iso-sweep direct compute head 64x48", "direct", false),
                ("iso-sweep meshlets compute head 64x48", "extract", true),
                ("iso-sweep meshlets compute head 64x48", "draw", false),
            ]
        );
        assert!((s[1].spread - 0.05).abs() < 1e-9);
        assert_eq!(s[1].medians_ms, [2.0, 2.1]);
        assert_eq!(
            report(&s),
            [
                "repeat check: 1 of 3 stages moved by more than 3 % between runs:",
                "  iso-sweep meshlets compute head 64x48 / extract: 2.000, 2.100 ms (5.0 %)",
            ]
        );
    }
}
