//! Who is watching: the pages that asked for a frame lately. The
//! simulation runs only while some page shows it, so a viewer left open in
//! a terminal does not keep a core busy with nobody looking, and a visitor
//! who opens the page late still finds the scene where it was.
//!
//! A page names itself with `?page=ID` (a random number it picks) on
//! `/api/frame`; a request without one counts as a page too.

use std::time::{Duration, Instant};

/// A page is watching when it asked for a frame within this time.
pub const WATCH_WINDOW: Duration = Duration::from_secs(1);
/// Pages remembered at most (the oldest is forgotten first).
const MAX_PAGES: usize = 64;

/// The pages seen lately, each with when it was last seen.
#[derive(Debug, Default)]
pub struct Watchers {
    pages: Vec<(u64, Instant)>,
}

impl Watchers {
    /// Page `id` (or an unnamed one, id 0) asked for a frame now.
    pub fn seen(&mut self, id: Option<u64>) {
        let (id, now) = (id.unwrap_or(0), Instant::now());
        if let Some(entry) = self.pages.iter_mut().find(|(page, _)| *page == id) {
            entry.1 = now;
            return;
        }
        self.pages
            .retain(|(_, last)| now.duration_since(*last) < WATCH_WINDOW);
        if self.pages.len() >= MAX_PAGES {
            self.pages.remove(0);
        }
        self.pages.push((id, now));
    }

    /// Pages that asked within [`WATCH_WINDOW`].
    pub fn count(&self) -> usize {
        let now = Instant::now();
        self.pages
            .iter()
            .filter(|(_, last)| now.duration_since(*last) < WATCH_WINDOW)
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pages_count_once_each_and_expire() {
        let mut watchers = Watchers::default();
        assert_eq!(watchers.count(), 0);
        watchers.seen(Some(7));
        watchers.seen(Some(7));
        watchers.seen(None);
        assert_eq!(watchers.count(), 2);
        let long_ago = watchers.pages[0].1.checked_sub(WATCH_WINDOW).unwrap();
        watchers.pages[0].1 = long_ago;
        assert_eq!(watchers.count(), 1);
        for id in 0..100 {
            watchers.seen(Some(id));
        }
        assert!(watchers.pages.len() <= MAX_PAGES);
    }
}
