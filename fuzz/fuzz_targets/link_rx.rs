//! Any byte stream into a receiving link, cut into the chunks the first byte chooses.
//! Beyond "never panics": `handle_input` always makes progress (or yields an event), every delivered payload
//! fits `MAX_PAYLOAD`, and the payloads delivered do not depend on how the stream was cut
//! (a second link fed each part whole, at the same times, delivers the same ones).
#![no_main]
use libfuzzer_sys::fuzz_target;
use protocol::link::{Config, Event, Link, MAX_FRAME};
use protocol::MAX_PAYLOAD;

/// Feeds `bytes` in chunks of `chunk`, collecting delivered payloads.
fn feed(link: &mut Link, now: u64, bytes: &[u8], chunk: usize, got: &mut Vec<Vec<u8>>) {
    for part in bytes.chunks(chunk) {
        let mut p = part;
        while !p.is_empty() {
            let (n, ev) = link.handle_input(now, p);
            // Zero bytes with an event is documented: a pending event or a buffered frame
            // comes out before more input is read.
            assert!(n > 0 || ev.is_some(), "no progress on {} bytes", p.len());
            assert!(n <= p.len());
            if let Some(Event::Data(d)) = ev {
                assert!(d.len() <= MAX_PAYLOAD);
                got.push(d.to_vec());
            }
            p = &p[n..];
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&c, rest)) = data.split_first() else {
        return;
    };
    let chunk = usize::from(c).max(1);
    let mut cut: Link = Link::new(Config::default());
    let mut whole: Link = Link::new(Config::default());
    let (mut got_cut, mut got_whole) = (Vec::new(), Vec::new());
    let mut now = 0;
    // Parts of 64 bytes arrive 7 ms apart; within a part the first link sees `chunk`-byte
    // reads, the second the whole part.
    for part in rest.chunks(64) {
        feed(&mut cut, now, part, chunk, &mut got_cut);
        feed(&mut whole, now, part, part.len(), &mut got_whole);
        now += 7;
        let mut out = [0u8; MAX_FRAME];
        while cut.poll_transmit(now, &mut out).is_some() {}
        while whole.poll_transmit(now, &mut out).is_some() {}
        cut.handle_timeout(now);
        whole.handle_timeout(now);
    }
    assert_eq!(got_cut, got_whole, "delivery depends on read sizes");
    assert_eq!(cut.counters(), whole.counters());
});
