//! Any byte stream into a receiving link, in the chunks the first byte chooses: it never
//! panics and handle_input always makes progress.
#![no_main]
use libfuzzer_sys::fuzz_target;
use protocol::link::{Config, Link, MAX_FRAME};

fuzz_target!(|data: &[u8]| {
    let Some((&c, rest)) = data.split_first() else { return };
    let chunk = usize::from(c).max(1);
    let mut link: Link = Link::new(Config::default());
    let mut now = 0;
    for part in rest.chunks(chunk) {
        let mut p = part;
        while !p.is_empty() {
            let (n, _) = link.handle_input(now, p);
            assert!(n > 0 || p.is_empty(), "no progress");
            p = &p[n..];
        }
        now += 7;
        let mut out = [0u8; MAX_FRAME];
        while link.poll_transmit(now, &mut out).is_some() {}
        link.handle_timeout(now);
    }
});
