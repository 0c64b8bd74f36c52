//! The machine's cores shared among the tool runs of `cargo xtask synth`: every Yosys and
//! nextpnr run is single-threaded, so the designs, their two Yosys passes and their
//! nextpnr seeds all start at once and each run waits for a core. Before, the designs ran
//! one after another and a core sat idle through every Yosys pass (the ray-casting core's
//! alone is three and a half minutes).
//!
//! A waiting run with the higher priority goes first (the synthesis flow gives each run
//! its design's expected cost, so the longest designs start first and none is left to
//! run alone at the end), then the one that asked first.

use std::sync::{Condvar, Mutex, MutexGuard, OnceLock};

struct State {
    free: usize,
    /// (priority, ticket) of each waiting run.
    waiting: Vec<(u32, u64)>,
    next: u64,
}

/// A number of cores and the runs waiting for one.
pub struct Cores {
    state: Mutex<State>,
    changed: Condvar,
}

/// A core held for one run; given back when dropped.
pub struct Core<'a>(&'a Cores);

impl Drop for Core<'_> {
    fn drop(&mut self) {
        let mut s = self.0.lock();
        s.free += 1;
        self.0.changed.notify_all();
    }
}

impl Cores {
    /// `n` cores, none taken.
    pub fn new(n: usize) -> Self {
        Self {
            state: Mutex::new(State {
                free: n,
                waiting: Vec::new(),
                next: 0,
            }),
            changed: Condvar::new(),
        }
    }

    /// A poisoned lock means a run panicked while counting: the count is still right.
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Waits for a free core: the waiting run of highest `priority` first, then the
    /// earliest.
    pub fn take(&self, priority: u32) -> Core<'_> {
        let mut s = self.lock();
        let ticket = s.next;
        s.next += 1;
        s.waiting.push((priority, ticket));
        loop {
            let first = s
                .waiting
                .iter()
                .copied()
                .max_by_key(|&(p, t)| (p, std::cmp::Reverse(t)));
            if s.free > 0 && first == Some((priority, ticket)) {
                break;
            }
            s = self.changed.wait(s).unwrap_or_else(|p| p.into_inner());
        }
        s.waiting.retain(|&(_, t)| t != ticket);
        s.free -= 1;
        self.changed.notify_all();
        Core(self)
    }

    /// How many runs are waiting.
    #[cfg(test)]
    fn waiting(&self) -> usize {
        self.lock().waiting.len()
    }
}

/// Waits for one of the machine's cores ([`Cores::take`]).
pub fn take(priority: u32) -> Core<'static> {
    static MACHINE: OnceLock<Cores> = OnceLock::new();
    MACHINE
        .get_or_init(|| Cores::new(std::thread::available_parallelism().map_or(1, |n| n.get())))
        .take(priority)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::time::Duration;

    #[test]
    fn never_more_runs_than_cores_and_every_run_gets_one() {
        let cores = Cores::new(2);
        let running = AtomicUsize::new(0);
        let most = AtomicUsize::new(0);
        let done = AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..11 {
                s.spawn(|| {
                    let _core = cores.take(0);
                    let now = running.fetch_add(1, Ordering::SeqCst) + 1;
                    most.fetch_max(now, Ordering::SeqCst);
                    std::thread::sleep(Duration::from_millis(5));
                    running.fetch_sub(1, Ordering::SeqCst);
                    done.fetch_add(1, Ordering::SeqCst);
                });
            }
        });
        assert_eq!(done.load(Ordering::SeqCst), 11);
        let most = most.load(Ordering::SeqCst);
        assert!(most <= 2, "{most} runs at once on 2 cores");
        assert_eq!(running.load(Ordering::SeqCst), 0);
    }

    #[test]
    fn a_waiting_run_of_higher_priority_goes_first() {
        let cores = Cores::new(1);
        let held = cores.take(0);
        let order = Mutex::new(Vec::new());
        std::thread::scope(|s| {
            for (k, p) in [1u32, 3, 2, 3].into_iter().enumerate() {
                let (cores, order) = (&cores, &order);
                s.spawn(move || {
                    let _core = cores.take(p);
                    order.lock().unwrap_or_else(|e| e.into_inner()).push((p, k));
                });
                // each queued before the next asks, so the tickets are in this order
                while cores.waiting() <= k {
                    std::thread::sleep(Duration::from_millis(1));
                }
            }
            drop(held);
        });
        let order = order.into_inner().unwrap_or_else(|e| e.into_inner());
        assert_eq!(order, [(3, 1), (3, 3), (2, 2), (1, 0)]);
    }
}
