//! The TCP server: a listener thread accepts agents; each gets the current value of every
//! item at once, then only changes. No client can slow the caller: publishing only appends a
//! change's bytes to each client's queue (under a lock held for that copy); each client's own
//! thread writes its queue to the socket, non-blocking, in chunks as large as the socket takes
//! (so a burst of changes, as virtual time makes them, costs few system calls, none on the
//! caller's thread), and reads its `* PING`s. A client whose queue would pass [`QUEUE_LIMIT`]
//! (it stopped reading) is dropped. When the adapter closes, each client's thread writes what
//! is still queued, for at most [`DRAIN_LIMIT`].

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime};

use super::items::{Current, Modes};
use crate::pulse_core::Status;

/// The heartbeat the adapter announces, ms (`* PONG <ms>`).
pub const HEARTBEAT_MS: u64 = 10_000;

/// The longest the adapter, when it closes, waits for its clients to take what is queued.
pub const DRAIN_LIMIT: Duration = Duration::from_secs(2);

/// The most a client may have waiting to be sent, bytes; more, and it is dropped.
pub const QUEUE_LIMIT: usize = 8 << 20;

struct Client {
    id: u64,
    stream: TcpStream,
    /// Bytes not yet handed to its socket, in order (its thread takes them out to write).
    queue: Vec<u8>,
}

impl Client {
    /// Queues `bytes`; false if the queue would pass the limit.
    fn send(&mut self, bytes: &[u8]) -> bool {
        if self.queue.len() + bytes.len() > QUEUE_LIMIT {
            return false;
        }
        self.queue.extend_from_slice(bytes);
        true
    }
}

#[derive(Default)]
struct Inner {
    clients: Vec<Client>,
    current: super::items::Current,
    /// The timestamp of the last publish: a connecting agent's dump carries it.
    current_ts: Option<SystemTime>,
    next_id: u64,
    connected_ever: u64,
    dropped: u64,
}

/// The SHDR adapter: a listening socket and its agents.
pub struct Adapter {
    inner: Arc<Mutex<Inner>>,
    addr: SocketAddr,
    stop: Arc<AtomicBool>,
}

impl Adapter {
    /// Listens on `addr` and starts accepting agents.
    pub fn start(addr: SocketAddr) -> Result<Adapter, String> {
        let listener = TcpListener::bind(addr)
            .map_err(|e| format!("mtconnect: cannot listen on {addr}: {e}"))?;
        let addr = listener
            .local_addr()
            .map_err(|e| format!("mtconnect: {e}"))?;
        listener
            .set_nonblocking(true)
            .map_err(|e| format!("mtconnect: {e}"))?;
        let inner = Arc::new(Mutex::new(Inner::default()));
        let stop = Arc::new(AtomicBool::new(false));
        let (i2, s2) = (inner.clone(), stop.clone());
        std::thread::Builder::new()
            .name("mtconnect-accept".into())
            .spawn(move || accept_loop(listener, i2, s2))
            .map_err(|e| format!("mtconnect: {e}"))?;
        Ok(Adapter { inner, addr, stop })
    }

    /// The address it listens on (the port chosen, for port 0).
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// Agents connected now.
    pub fn clients(&self) -> usize {
        self.inner.lock().map(|i| i.clients.len()).unwrap_or(0)
    }

    /// Bytes waiting in the agents' queues now.
    pub fn queued(&self) -> usize {
        self.inner
            .lock()
            .map(|i| i.clients.iter().map(|c| c.queue.len()).sum())
            .unwrap_or(0)
    }

    /// Agents dropped because they stopped reading.
    pub fn dropped(&self) -> u64 {
        self.inner.lock().map(|i| i.dropped).unwrap_or(0)
    }

    /// Waits until an agent has connected (at any time so far), at most `limit`.
    pub fn wait_for_agent(&self, limit: Duration) -> bool {
        let end = Instant::now() + limit;
        loop {
            if self
                .inner
                .lock()
                .map(|i| i.connected_ever > 0)
                .unwrap_or(false)
            {
                return true;
            }
            if Instant::now() >= end {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// Takes a snapshot's items at time `ts`: sends the ones that changed since the last call
    /// to every agent (nothing if none changed), stamped `ts`. Never blocks on a client.
    pub fn publish<K: Into<super::Key>>(&self, items: Vec<(K, String)>, ts: SystemTime) {
        let items = items.into_iter().map(|(k, v)| (k.into(), v)).collect();
        self.update(ts, |c| c.replace(items));
    }

    /// [`Adapter::publish`] of the mill's items ([`super::items`]) of `s` with `m`, made only
    /// where their inputs changed.
    pub fn publish_mill(&self, s: &Status, m: &Modes, ts: SystemTime) {
        self.update(ts, |c| c.update_mill(s, m));
    }

    /// Updates the current values with `f` and sends what changed.
    fn update(&self, ts: SystemTime, f: impl FnOnce(&mut Current)) {
        let Ok(mut g) = self.inner.lock() else {
            return;
        };
        let inner = &mut *g;
        f(&mut inner.current);
        let c = &inner.current;
        if c.changed.is_empty() {
            return;
        }
        inner.current_ts = Some(ts);
        if inner.clients.is_empty() {
            return;
        }
        let text = super::shdr::lines_of(
            &super::shdr::timestamp(ts),
            c.changed
                .iter()
                .map(|&i| (c.values[i].0.as_ref(), c.values[i].1.as_str())),
        );
        let before = inner.clients.len();
        inner.clients.retain_mut(|c| c.send(text.as_bytes()));
        inner.dropped += (before - inner.clients.len()) as u64;
    }
}

impl Drop for Adapter {
    fn drop(&mut self) {
        // Each client's thread writes what is queued (at most DRAIN_LIMIT), closes and leaves.
        self.stop.store(true, Ordering::SeqCst);
        let end = Instant::now() + DRAIN_LIMIT + Duration::from_millis(500);
        while Instant::now() < end && self.clients() > 0 {
            std::thread::sleep(Duration::from_millis(5));
        }
        if let Ok(mut g) = self.inner.lock() {
            for c in g.clients.drain(..) {
                let _ = c.stream.shutdown(std::net::Shutdown::Both);
            }
        }
    }
}

fn accept_loop(listener: TcpListener, inner: Arc<Mutex<Inner>>, stop: Arc<AtomicBool>) {
    while !stop.load(Ordering::SeqCst) {
        match listener.accept() {
            Ok((stream, _)) => {
                let _ = stream.set_nodelay(true);
                if stream.set_nonblocking(true).is_err() {
                    continue;
                }
                let Ok(reader) = stream.try_clone() else {
                    continue;
                };
                let Ok(mut g) = inner.lock() else {
                    return;
                };
                let id = g.next_id;
                g.next_id += 1;
                g.connected_ever += 1;
                let mut c = Client {
                    id,
                    stream,
                    queue: Vec::new(),
                };
                let ts = g.current_ts.unwrap_or_else(SystemTime::now);
                let dump = super::shdr::lines(&super::shdr::timestamp(ts), &g.current.values);
                if c.send(dump.as_bytes()) {
                    g.clients.push(c);
                    let (i2, s2) = (inner.clone(), stop.clone());
                    let _ = std::thread::Builder::new()
                        .name("mtconnect-client".into())
                        .spawn(move || client_loop(id, reader, i2, s2));
                } else {
                    g.dropped += 1;
                }
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(5))
            }
            Err(_) => std::thread::sleep(Duration::from_millis(50)),
        }
    }
}

/// Writes as much of `bytes` as the socket takes now: how much; None if the client is gone.
fn write_some(stream: &mut TcpStream, bytes: &[u8]) -> Option<usize> {
    let mut done = 0;
    while done < bytes.len() {
        match stream.write(&bytes[done..]) {
            Ok(0) => return None,
            Ok(n) => done += n,
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) if e.kind() == ErrorKind::WouldBlock => break,
            Err(_) => return None,
        }
    }
    Some(done)
}

/// A client's thread: writes its queue to the socket as far as the socket takes it, and reads
/// its lines: `* PING` is answered with `* PONG <ms>` (after what is queued); anything else is
/// ignored. It sleeps 10 ms when there was nothing to do. The client is removed when it closes
/// or fails; when the adapter stops, what is queued is written (at most [`DRAIN_LIMIT`]) and
/// the socket closed.
fn client_loop(id: u64, mut sock: TcpStream, inner: Arc<Mutex<Inner>>, stop: Arc<AtomicBool>) {
    let mut buf = Vec::new();
    let mut chunk = [0u8; 512];
    let mut drain_end = None;
    loop {
        let stopping = stop.load(Ordering::SeqCst);
        if stopping && drain_end.is_none() {
            drain_end = Some(Instant::now() + DRAIN_LIMIT);
        }
        // Take the queue out, write it outside the lock, put back what the socket did not take
        // in front of what came meanwhile.
        let Some(mut out) = (match inner.lock() {
            Ok(mut g) => g
                .clients
                .iter_mut()
                .find(|c| c.id == id)
                .map(|c| std::mem::take(&mut c.queue)),
            Err(_) => None,
        }) else {
            return; // dropped by the publisher
        };
        let mut busy = false;
        let mut gone = false;
        if !out.is_empty() {
            match write_some(&mut sock, &out) {
                None => gone = true,
                Some(n) => {
                    busy = n > 0;
                    out.drain(..n);
                }
            }
        }
        let done_draining = out.is_empty() || drain_end.is_some_and(|e| Instant::now() >= e);
        if let Ok(mut g) = inner.lock() {
            if let Some(i) = g.clients.iter().position(|c| c.id == id) {
                if gone || (stopping && done_draining) {
                    let c = g.clients.remove(i);
                    let _ = c.stream.shutdown(std::net::Shutdown::Both);
                    return;
                }
                if !out.is_empty() {
                    out.extend_from_slice(&g.clients[i].queue);
                    g.clients[i].queue = out;
                }
            } else {
                return;
            }
        }
        if !stopping {
            match sock.read(&mut chunk) {
                Ok(0) => gone = true,
                Ok(n) => {
                    busy = true;
                    buf.extend_from_slice(&chunk[..n]);
                    while let Some(p) = buf.iter().position(|&b| b == b'\n') {
                        let line: Vec<u8> = buf.drain(..=p).collect();
                        if String::from_utf8_lossy(&line)
                            .trim_end()
                            .starts_with("* PING")
                        {
                            let pong = format!("* PONG {HEARTBEAT_MS}\n");
                            let Ok(mut g) = inner.lock() else { return };
                            let g = &mut *g;
                            if let Some(i) = g.clients.iter().position(|c| c.id == id) {
                                if !g.clients[i].send(pong.as_bytes()) {
                                    g.clients.remove(i);
                                    g.dropped += 1;
                                }
                            }
                        }
                    }
                    if buf.len() > 4096 {
                        buf.clear();
                    }
                }
                Err(e)
                    if e.kind() == ErrorKind::WouldBlock || e.kind() == ErrorKind::Interrupted => {}
                Err(_) => gone = true,
            }
            if gone {
                if let Ok(mut g) = inner.lock() {
                    g.clients.retain(|c| c.id != id);
                }
                return;
            }
        }
        if !busy {
            std::thread::sleep(Duration::from_millis(if stopping { 1 } else { 10 }));
        }
    }
}
