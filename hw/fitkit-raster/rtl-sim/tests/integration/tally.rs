//! Per-class bookkeeping of the cycle comparison: every case's difference between the
//! RTL's counters and the model's (which must be none: the model's timing is the RTL's,
//! docs/rtl.md "Cycle formulas"), grouped, so a failure reports each distinct difference
//! of each class with its count and a case that shows it.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::ops::{Add, Sub};

use crate::harness::Step;

/// RTL minus model, per counter, for one command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Default)]
pub struct Delta {
    pub line: i64,
    pub triangle: i64,
    pub clear: i64,
    pub fragments: i64,
    pub packets: i64,
}

impl Add for Delta {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            line: self.line + o.line,
            triangle: self.triangle + o.triangle,
            clear: self.clear + o.clear,
            fragments: self.fragments + o.fragments,
            packets: self.packets + o.packets,
        }
    }
}

impl Sub for Delta {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self {
            line: self.line - o.line,
            triangle: self.triangle - o.triangle,
            clear: self.clear - o.clear,
            fragments: self.fragments - o.fragments,
            packets: self.packets - o.packets,
        }
    }
}

impl Delta {
    pub fn of(s: &Step) -> Self {
        let d = |a: u64, b: u64| a as i64 - b as i64;
        Self {
            line: d(s.rtl.line, s.model.line),
            triangle: d(s.rtl.triangle, s.model.triangle),
            clear: d(s.rtl.clear, s.model.clear),
            fragments: d(s.rtl.fragments, s.model.fragments),
            packets: d(s.rtl.packets, s.model.packets),
        }
    }
}

#[derive(Default)]
struct Class {
    cases: u64,
    diffs: BTreeMap<Delta, (u64, String)>,
}

/// The differences of one test, by case class.
#[derive(Default)]
pub struct Tally {
    classes: BTreeMap<&'static str, Class>,
}

impl Tally {
    /// Records a step under `class`, expecting the RTL and the model to agree on every
    /// counter; `case` names it for the report.
    pub fn add(&mut self, class: &'static str, case: impl FnOnce() -> String, step: &Step) {
        let c = self.classes.entry(class).or_default();
        c.cases += 1;
        let d = Delta::of(step);
        if d != Delta::default() {
            c.diffs
                .entry(d)
                .and_modify(|e| e.0 += 1)
                .or_insert_with(|| {
                    (
                        1,
                        format!("{} (rtl {:?}, model {:?})", case(), step.rtl, step.model),
                    )
                });
        }
    }

    /// Cases recorded over all classes.
    pub fn cases(&self) -> u64 {
        self.classes.values().map(|c| c.cases).sum()
    }

    /// Every class's differences, or `None` if there are none.
    pub fn report(&self) -> Option<String> {
        let mut out = String::new();
        for (name, c) in &self.classes {
            for (d, (n, example)) in &c.diffs {
                let _ = writeln!(
                    out,
                    "{name}: {n} of {} cases differ by {d:?}, e.g. {example}",
                    c.cases
                );
            }
        }
        (!out.is_empty()).then_some(out)
    }

    /// Panics with the report unless the RTL and the model agree on every counter.
    pub fn assert_exact(&self) {
        if let Some(r) = self.report() {
            panic!("RTL and model counters differ (RTL minus model):\n{r}");
        }
    }
}
