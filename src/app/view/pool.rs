//! The viewer's open connections: at most a fixed number at once, and
//! when a new one arrives at a full pool, the connection that has been
//! *waiting* longest (idle between requests, still receiving a slow
//! request, or sending a response its client does not read) is closed to
//! make room. A connection whose response is being prepared is never
//! closed.
//!
//! Why: with one thread per connection and a fixed cap, a client that opens
//! the cap's worth of silent connections (and reopens them as they time
//! out) used to starve everyone else until the idle timeout. With eviction
//! of the oldest waiting connection, a new client is always served: the
//! silent ones are the oldest and go first. A page's own kept-alive
//! connection stays young, because each request it sends restarts its
//! wait.
//!
//! Cost: `O(capacity)` per accepted connection (a scan for the oldest).

use std::net::{Shutdown, TcpStream};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Instant;

/// One open connection: a handle to close it, and since when it waits
/// (`None` while a response is being prepared or sent).
struct Slot {
    id: u64,
    stream: TcpStream,
    waiting_since: Option<Instant>,
}

/// The open connections (see the module header).
pub struct Pool {
    capacity: usize,
    state: Mutex<State>,
}

struct State {
    slots: Vec<Slot>,
    next_id: u64,
}

/// A connection's place in the pool; leaves it when dropped.
pub struct Member {
    pool: Arc<Pool>,
    id: u64,
}

impl Pool {
    /// An empty pool of at most `capacity` connections.
    pub fn new(capacity: usize) -> Arc<Pool> {
        Arc::new(Pool {
            capacity,
            state: Mutex::new(State {
                slots: Vec::with_capacity(capacity),
                next_id: 0,
            }),
        })
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A connection thread that panicked leaves consistent data behind.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Admits `stream` (waiting for its first request), closing the
    /// connection that has waited longest if the pool is full; `None` (the
    /// caller drops the stream) when it is full of connections being
    /// answered, or the stream cannot be cloned.
    pub fn admit(self: &Arc<Pool>, stream: &TcpStream) -> Option<Member> {
        let handle = stream.try_clone().ok()?;
        let mut state = self.lock();
        if state.slots.len() >= self.capacity {
            let oldest = state
                .slots
                .iter()
                .enumerate()
                .filter_map(|(index, slot)| slot.waiting_since.map(|since| (since, index)))
                .min()?
                .1;
            let evicted = state.slots.swap_remove(oldest);
            // Its thread's read returns at once and the thread ends.
            let _ = evicted.stream.shutdown(Shutdown::Both);
        }
        let id = state.next_id;
        state.next_id += 1;
        state.slots.push(Slot {
            id,
            stream: handle,
            waiting_since: Some(Instant::now()),
        });
        Some(Member {
            pool: Arc::clone(self),
            id,
        })
    }

    /// How many connections are open.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.lock().slots.len()
    }
}

impl Member {
    /// The connection now answers a request: it may not be closed.
    pub fn answering(&self) {
        self.set_waiting(None);
    }

    /// The connection now waits for its next request.
    pub fn waiting(&self) {
        self.set_waiting(Some(Instant::now()));
    }

    fn set_waiting(&self, since: Option<Instant>) {
        let mut state = self.pool.lock();
        if let Some(slot) = state.slots.iter_mut().find(|slot| slot.id == self.id) {
            slot.waiting_since = since;
        }
    }
}

impl Drop for Member {
    fn drop(&mut self) {
        let mut state = self.pool.lock();
        if let Some(index) = state.slots.iter().position(|slot| slot.id == self.id) {
            state.slots.swap_remove(index);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;
    use std::net::TcpListener;

    /// A connected pair: (client side, server side).
    fn pair(listener: &TcpListener) -> (TcpStream, TcpStream) {
        let client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (server, _) = listener.accept().unwrap();
        (client, server)
    }

    #[test]
    fn a_full_pool_closes_the_connection_waiting_longest_but_never_one_being_answered() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let pool = Pool::new(2);
        let (mut first_client, first) = pair(&listener);
        let (_second_client, second) = pair(&listener);
        let first_member = pool.admit(&first).unwrap();
        let second_member = pool.admit(&second).unwrap();
        second_member.answering();
        let (_third_client, third) = pair(&listener);
        let third_member = pool.admit(&third).unwrap();
        assert_eq!(pool.len(), 2);
        // the first (waiting longest) was shut down: its client reads EOF
        let mut byte = [0u8; 1];
        assert_eq!(first_client.read(&mut byte).unwrap(), 0);
        drop(first_member); // its thread ends: nothing else leaves
        assert_eq!(pool.len(), 2);
        // now one waits (third) and one is answered (second): third goes
        let (_fourth_client, fourth) = pair(&listener);
        let fourth_member = pool.admit(&fourth).unwrap();
        assert_eq!(pool.len(), 2);
        drop(third_member);
        // both remaining are answered: a new one is refused
        fourth_member.answering();
        let (_fifth_client, fifth) = pair(&listener);
        assert!(pool.admit(&fifth).is_none());
        drop(second_member);
        assert_eq!(pool.len(), 1);
    }
}
