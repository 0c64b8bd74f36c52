//! The run: cases spread over worker threads, each case a pure function of `(seed,
//! index)` run inside `catch_unwind` with a panic hook that records where it panicked.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use protocol::frame::Numeric;
use rand::rngs::SmallRng;
use rand::SeedableRng;
use sim_target::num::instrumented;

use super::damage::parse_case;
use super::raster::raster_case;
use super::report::{AcneCase, AcneList, CaseResult, Counts, Failure, Report, MAX_FAILURES};
use super::rt::rt_case;
use super::{Category, Config, StressError};

/// The category of case `index` when `only` is not given.
pub fn category_of(index: u64, only: Option<Category>) -> Category {
    only.unwrap_or(Category::ALL[(index % 3) as usize])
}

fn case_rng(seed: u64, index: u64, cat: Category) -> SmallRng {
    let mut x = seed ^ 0x5851_f42d_4c95_7f2d_u64.wrapping_mul(index.wrapping_add(1));
    x ^= (cat as u64) << 61;
    // splitmix64 so that neighbouring indices give unrelated streams
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    SmallRng::seed_from_u64(x ^ (x >> 31))
}

thread_local! {
    /// Where the last panic on this thread happened (filled by the run's panic hook).
    static PANIC_AT: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
    /// This thread is one of a run's workers: the run's panic hook records its panics
    /// instead of passing them on.
    static IN_CASE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// What [`std::panic::take_hook`] returns.
type PanicHook = Box<dyn Fn(&std::panic::PanicHookInfo<'_>) + Sync + Send + 'static>;

/// Held by a run while its panic hook is installed. The hook is the process's: runs that
/// overlapped (tests on parallel threads) would each put back the hook they found, the
/// last one to finish possibly a silencing one, for good.
static HOOK: Mutex<()> = Mutex::new(());

/// Puts back the hook a run found, once the run's own (which shares it) is gone.
fn restore_hook(hook: Arc<PanicHook>) {
    drop(std::panic::take_hook());
    match Arc::try_unwrap(hook) {
        Ok(hook) => std::panic::set_hook(hook),
        Err(shared) => std::panic::set_hook(Box::new(move |info| shared(info))),
    }
}

/// Runs one case, catching a panic, on a private one-thread pool (so that the renders
/// that are parallel over rows stay on this thread, where the panic hook records a
/// panic's location). Panics are caught but still reported by the current panic hook;
/// [`run`] silences it.
pub fn run_case(
    seed: u64,
    index: u64,
    only: Option<Category>,
) -> Result<(Category, CaseResult), StressError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| StressError::Pool(e.to_string()))?;
    Ok(pool.install(|| case_on_this_thread(seed, index, only, AcneList::Off)))
}

/// [`run_case`] on the calling thread, which must be the only thread of the current rayon
/// pool.
fn case_on_this_thread(
    seed: u64,
    index: u64,
    only: Option<Category>,
    acne: AcneList,
) -> (Category, CaseResult) {
    let cat = category_of(index, only);
    let mut rng = case_rng(seed, index, cat);
    instrumented::set_nan_trap(trap());
    let out = catch_unwind(AssertUnwindSafe(|| match cat {
        Category::Raster => raster_case(&mut rng),
        Category::Rt => rt_case(&mut rng, acne == AcneList::Pixels),
        Category::Parse => parse_case(&mut rng),
    }));
    let mut r = match out {
        Ok(r) => r,
        Err(e) => {
            let msg = e
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| e.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "non-string panic".into());
            let at = PANIC_AT.with(|p| std::mem::take(&mut *p.borrow_mut()));
            CaseResult {
                counts: Counts {
                    panics: 1,
                    ..Counts::default()
                },
                formats: Default::default(),
                failure: Some(format!("panic: {msg}{at}")),
                acne: None,
            }
        }
    };
    r.counts.cases = 1;
    if r.failure.is_none() && r.counts.failed() {
        r.failure = Some(format!("{:?}", r.counts));
    }
    (cat, r)
}

/// Debugging aid (`FPGFX_STRESS_TRAP=1` with `--case K`): stop at the first NaN and say
/// where it came from ([`instrumented::set_nan_trap`]).
fn trap() -> bool {
    static TRAP: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *TRAP.get_or_init(|| std::env::var_os("FPGFX_STRESS_TRAP").is_some())
}

/// Runs `cfg.cases` cases (or the one of `cfg.case`) on all cores. Each worker thread owns
/// a one-thread rayon pool, so a render that is parallel over rows stays on that thread
/// (its panics are located, and the workers do not contend for one global pool); the
/// probed renders run on the calling thread anyway, each inside its own count scope.
pub fn run(cfg: &Config) -> Result<Report, StressError> {
    let started = Instant::now();
    let indices: Vec<u64> = match cfg.case {
        Some(k) => vec![k],
        None => (0..cfg.cases).collect(),
    };
    let threads = if cfg.threads == 0 {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    } else {
        cfg.threads
    };
    let next = AtomicU64::new(0);
    let total = Mutex::new(Report {
        seed: cfg.seed,
        ..Report::default()
    });
    // A panicking case is counted, not printed: its panics skip the previous hook
    // meanwhile, and every other thread's still reach it (the process may be running
    // other work, such as other tests, beside this run).
    let _one_hook = HOOK.lock().unwrap_or_else(|p| p.into_inner());
    let hook: Arc<PanicHook> = Arc::new(std::panic::take_hook());
    let others = hook.clone();
    std::panic::set_hook(Box::new(move |info| {
        if !IN_CASE.get() {
            return others(info);
        }
        let at = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        PANIC_AT.with(|p| *p.borrow_mut() = at);
    }));
    let pools: Result<Vec<rayon::ThreadPool>, StressError> = (0..threads)
        .map(|_| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .map_err(|e| StressError::Pool(e.to_string()))
        })
        .collect();
    let pools = match pools {
        Ok(p) => p,
        Err(e) => {
            restore_hook(hook);
            return Err(e);
        }
    };
    std::thread::scope(|sc| {
        for pool in &pools {
            sc.spawn(|| {
                pool.install(|| {
                    IN_CASE.set(true);
                    let mut local = Report::default();
                    loop {
                        let k = next.fetch_add(1, Ordering::Relaxed) as usize;
                        let Some(&index) = indices.get(k) else { break };
                        let (cat, mut r) = case_on_this_thread(cfg.seed, index, cfg.only, cfg.acne);
                        if cfg.acne != AcneList::Off {
                            local.acne.extend(acne_case(index, &mut r));
                        }
                        local.by_category[cat as usize].add(&r.counts);
                        for (a, b) in local.by_format.iter_mut().zip(&r.formats) {
                            a.add(b);
                        }
                        if let Some(what) = r.failure {
                            local.failures.push(Failure {
                                category: cat,
                                index,
                                what,
                            });
                        }
                    }
                    let mut t = total.lock().unwrap_or_else(|p| p.into_inner());
                    for (a, b) in t.by_category.iter_mut().zip(&local.by_category) {
                        a.add(b);
                    }
                    for (a, b) in t.by_format.iter_mut().zip(&local.by_format) {
                        a.add(b);
                    }
                    t.failures.extend(local.failures);
                    t.acne.extend(local.acne);
                    IN_CASE.set(false);
                });
            });
        }
    });
    restore_hook(hook);
    let mut report = total.into_inner().unwrap_or_else(|p| p.into_inner());
    report.failures.sort_by_key(|f| f.index);
    report.failures.truncate(MAX_FAILURES);
    report.acne.sort_by_key(|c| c.index);
    report.seconds = started.elapsed().as_secs_f64();
    Ok(report)
}

/// Case `index`'s entry in [`Report::acne`], if its render left lit pixels black (an rt
/// case renders in one format: the one with a render).
fn acne_case(index: u64, r: &mut CaseResult) -> Option<AcneCase> {
    let c = &r.counts;
    if c.acne + c.acne_out_of_range == 0 {
        return None;
    }
    let fmt = r.formats.iter().position(|f| f.renders > 0).unwrap_or(0);
    Some(AcneCase {
        index,
        numeric: Numeric::ALL[fmt],
        pixels: if c.acne > 0 {
            c.acne
        } else {
            c.acne_out_of_range
        },
        checked: c.acne_checked,
        beyond_range: c.acne == 0,
        detail: r.acne.take(),
    })
}
