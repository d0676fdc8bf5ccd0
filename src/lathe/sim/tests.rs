//! Unit tests of the simulator (docs/lathe-sim.md).

use super::testkit::*;
#[allow(unused_imports)]
use super::*;

#[test]
fn smoke() {
    let mut l = sample_lathe(5).unwrap();
    l.start();
    let o = l.run_until_idle(600_000_000_000);
    eprintln!("{o:?} {} {:?}", l.summary(), l.stats());
}
