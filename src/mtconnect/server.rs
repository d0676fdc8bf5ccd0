//! The TCP server: a listener thread accepts agents; each gets the current value of every
//! item at once, then only changes. Every socket is non-blocking, and no client can slow the
//! caller: what a client's kernel buffer cannot take now waits in its own queue (a burst of
//! changes, as virtual time makes them), flushed at the next publish and by the client's reader
//! thread every 10 ms; a client whose queue would pass [`QUEUE_LIMIT`] (it stopped reading) is
//! dropped. The caller publishes from its own thread; the lock it takes is held only while
//! bytes are copied into kernel buffers or the queue.

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant, SystemTime};

/// The heartbeat the adapter announces, ms (`* PONG <ms>`).
pub const HEARTBEAT_MS: u64 = 10_000;

/// The longest the adapter, when it closes, waits for its clients to take what is queued.
const DRAIN_LIMIT: Duration = Duration::from_secs(2);

/// The most a client may have waiting to be sent, bytes; more, and it is dropped.
pub const QUEUE_LIMIT: usize = 4 << 20;

struct Client {
    id: u64,
    stream: TcpStream,
    /// Bytes its kernel buffer could not take yet, in order, from `head` on.
    queue: Vec<u8>,
    head: usize,
}

impl Client {
    /// Sends `bytes` after what is queued, without blocking: what the socket cannot take now is
    /// queued. False if the client is gone or its queue would pass the limit.
    fn send(&mut self, bytes: &[u8]) -> bool {
        if !self.flush() {
            return false;
        }
        let done = if self.queue.is_empty() {
            match write_some(&mut self.stream, bytes) {
                Some(n) => n,
                None => return false,
            }
        } else {
            0
        };
        let rest = &bytes[done..];
        if self.queue.len() - self.head + rest.len() > QUEUE_LIMIT {
            return false;
        }
        self.queue.extend_from_slice(rest);
        true
    }

    /// Writes what is queued as far as the socket takes it; false if the client is gone.
    fn flush(&mut self) -> bool {
        if self.queue.is_empty() {
            return true;
        }
        match write_some(&mut self.stream, &self.queue[self.head..]) {
            Some(n) => {
                self.head += n;
                // Compact only when the sent part is the larger: no copying of the whole queue
                // at every publish.
                if self.head == self.queue.len() {
                    self.queue.clear();
                    self.head = 0;
                } else if self.head > self.queue.len() / 2 {
                    self.queue.drain(..self.head);
                    self.head = 0;
                }
                true
            }
            None => false,
        }
    }
}

#[derive(Default)]
struct Inner {
    clients: Vec<Client>,
    current: Vec<(&'static str, String)>,
    /// The timestamp of the last publish: a connecting agent's dump carries it.
    current_ts: Option<SystemTime>,
    next_id: u64,
    connected_ever: u64,
    dropped: u64,
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
    pub fn publish(&self, items: Vec<(&'static str, String)>, ts: SystemTime) {
        let Ok(mut g) = self.inner.lock() else {
            return;
        };
        let inner = &mut *g;
        // The items come in a fixed order: compared pairwise (by key when the order differs).
        let same_keys = items.len() == inner.current.len()
            && items.iter().zip(&inner.current).all(|(a, b)| a.0 == b.0);
        let changed: Vec<(&'static str, String)> = if same_keys {
            items
                .iter()
                .zip(&inner.current)
                .filter(|(a, b)| a.1 != b.1)
                .map(|(a, _)| a.clone())
                .collect()
        } else {
            items
                .iter()
                .filter(|(k, v)| !inner.current.iter().any(|(ck, cv)| ck == k && cv == v))
                .cloned()
                .collect()
        };
        inner.current = items;
        if changed.is_empty() {
            return;
        }
        inner.current_ts = Some(ts);
        if inner.clients.is_empty() {
            return;
        }
        let text = super::shdr::lines(&super::shdr::timestamp(ts), &changed);
        let before = inner.clients.len();
        inner.clients.retain_mut(|c| c.send(text.as_bytes()));
        inner.dropped += (before - inner.clients.len()) as u64;
    }
}

impl Drop for Adapter {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        // What is still queued goes out before the sockets close (the end of a script's burst),
        // waiting at most DRAIN_LIMIT in all.
        let end = Instant::now() + DRAIN_LIMIT;
        if let Ok(mut g) = self.inner.lock() {
            for mut c in g.clients.drain(..) {
                let left = end.saturating_duration_since(Instant::now());
                if !c.queue.is_empty() && !left.is_zero() {
                    let _ = c.stream.set_nonblocking(false);
                    let _ = c.stream.set_write_timeout(Some(left));
                    let _ = c.stream.write_all(&c.queue[c.head..]);
                }
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
                    head: 0,
                };
                let ts = g.current_ts.unwrap_or_else(SystemTime::now);
                let dump = super::shdr::lines(&super::shdr::timestamp(ts), &g.current);
                if c.send(dump.as_bytes()) {
                    g.clients.push(c);
                    let (i2, s2) = (inner.clone(), stop.clone());
                    let _ = std::thread::Builder::new()
                        .name("mtconnect-client".into())
                        .spawn(move || read_loop(id, reader, i2, s2));
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

/// Reads an agent's lines: `* PING` is answered with `* PONG <ms>`; anything else is ignored.
/// The client is removed when it closes.
fn read_loop(id: u64, mut reader: TcpStream, inner: Arc<Mutex<Inner>>, stop: Arc<AtomicBool>) {
    let mut buf = Vec::new();
    let mut chunk = [0u8; 512];
    while !stop.load(Ordering::SeqCst) {
        match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => {
                buf.extend_from_slice(&chunk[..n]);
                while let Some(p) = buf.iter().position(|&b| b == b'\n') {
                    let line: Vec<u8> = buf.drain(..=p).collect();
                    let line = String::from_utf8_lossy(&line);
                    if line.trim_end().starts_with("* PING") {
                        let Ok(mut g) = inner.lock() else { return };
                        let pong = format!("* PONG {HEARTBEAT_MS}\n");
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
            Err(e) if e.kind() == ErrorKind::WouldBlock || e.kind() == ErrorKind::Interrupted => {
                std::thread::sleep(Duration::from_millis(10))
            }
            Err(_) => break,
        }
        // A client dropped by the publisher ends its reader too; a client with bytes queued
        // gets them as its socket takes them.
        if let Ok(mut g) = inner.lock() {
            let Some(i) = g.clients.iter().position(|c| c.id == id) else {
                return;
            };
            if !g.clients[i].flush() {
                g.clients.remove(i);
                return;
            }
        }
    }
    if let Ok(mut g) = inner.lock() {
        g.clients.retain(|c| c.id != id);
    }
}
