//! The queue points (docs/lathe-sim.md "Transfers, chucks and interlocks", seed 004 lines
//! 136–142, 288, 330): the receive block's M10 on an empty spindle and the delivery block's
//! M11 holding a work, with the chuck interlock.

use super::exec::Flow;
use super::{Event, Exec, Lathe, WaitOn};

impl Lathe {
    /// The receive queue point (M10 on an empty spindle).
    pub(super) fn recv_offer(&mut self, i: usize) -> Flow {
        match self.desc.supplier_of(i) {
            None if i == self.desc.supplier => {
                if self.supplied >= self.target {
                    self.chans[i].waits = Some(WaitOn::BarFeeder);
                    self.chans[i].exec = Exec::RecvOffer;
                    return Flow::Yield;
                }
                self.supplied += 1;
                let w = self.supplied;
                let c = &mut self.chans[i];
                c.work = Some(w);
                c.closed = true;
                self.transfer(None, Some(i), w, true);
                self.finish(i);
                Flow::Next
            }
            None => self.alarm(
                i,
                format!("M10 on an empty spindle: CH{} has no supplier", i + 1),
            ),
            Some(p) => {
                let s = &self.chans[p];
                let offered = match (&s.exec, s.work, s.closed) {
                    (Exec::Deliver, Some(w), true) => Some(w),
                    _ => None,
                };
                if let Some(w) = offered {
                    let c = &mut self.chans[i];
                    c.work = Some(w);
                    c.closed = true;
                    c.exec = Exec::RecvRelease { from: p, work: w };
                    self.busy = true;
                    return Flow::Next;
                }
                self.chans[i].waits = Some(WaitOn::Channel(p));
                self.chans[i].exec = Exec::RecvOffer;
                Flow::Yield
            }
        }
    }

    /// The delivery queue point (M11 holding a work): opens only once the receiver has closed
    /// on the work, or to the unloader.
    pub(super) fn deliver(&mut self, i: usize) -> Flow {
        let Some(w) = self.chans[i].work else {
            self.finish(i);
            return Flow::Next;
        };
        match self.desc.receiver_of(i) {
            None if i == self.desc.unloader => {
                self.delivered += 1;
                let c = &mut self.chans[i];
                c.work = None;
                c.closed = false;
                self.transfer(Some(i), None, w, true);
                self.finish(i);
                Flow::Next
            }
            None => self.alarm(
                i,
                format!("M11 holding work {w}: CH{} has no receiver", i + 1),
            ),
            Some(r) => {
                let rc = &self.chans[r];
                if rc.work == Some(w) && rc.closed {
                    let both = rc.closed && self.chans[i].closed;
                    let c = &mut self.chans[i];
                    c.work = None;
                    c.closed = false;
                    self.transfer(Some(i), Some(r), w, both);
                    self.finish(i);
                    return Flow::Next;
                }
                self.chans[i].waits = Some(WaitOn::Channel(r));
                self.chans[i].exec = Exec::Deliver;
                Flow::Yield
            }
        }
    }

    /// Records a work passing between chucks.
    fn transfer(&mut self, from: Option<usize>, to: Option<usize>, work: u32, both: bool) {
        self.busy = true;
        if self.record {
            self.events.push(Event::Transfer {
                t: self.t,
                from,
                to,
                work,
                both_closed: both,
            });
        }
    }
}
