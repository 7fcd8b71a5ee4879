//! `rigid`'s periodic full search (live tier) on a thread of its own. The
//! solve it falls due in resumes at once, as the solves around it do, and
//! a later solve takes up the motions the search kept, so that no answer
//! waits for a whole search while the scene goes on being explained.

use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use super::resume::SceneIds;
use crate::methods::{RigidTrack, rigid_solve_from};
use crate::{Params, Problem};

/// A full search running, or ended and not yet taken up.
#[derive(Debug, Clone)]
pub(super) struct Search {
    /// Shared so that the engine stays `Clone`; `None` once taken.
    thread: Arc<Mutex<Option<JoinHandle<Option<RigidTrack>>>>>,
    /// The engine's count of full searches when this one started: one
    /// run on the solve's own thread since (the scene changed) leaves this
    /// one's motions behind.
    pub(super) generation: u64,
    /// The views it searched.
    pub(super) scene: SceneIds,
}

impl Search {
    /// Starts a full search of `problem`; `None` when no thread could be
    /// started (the solve then searches on its own thread, as it would
    /// without this).
    /// `begin` runs first on the search's thread (to lower its priority,
    /// say).
    pub(super) fn start(
        problem: Problem,
        params: Params,
        generation: u64,
        scene: SceneIds,
        begin: Option<fn()>,
    ) -> Option<Self> {
        let thread = std::thread::Builder::new()
            .name("vref-rigid-search".into())
            .spawn(move || {
                if let Some(begin) = begin {
                    begin();
                }
                rigid_solve_from(&problem, &params, None).1
            })
            .ok()?;
        Some(Self {
            thread: Arc::new(Mutex::new(Some(thread))),
            generation,
            scene,
        })
    }

    /// Whether the search has ended (or was taken), without waiting.
    pub(super) fn has_ended(&self) -> bool {
        self.thread
            .lock()
            .map_or(true, |slot| slot.as_ref().is_none_or(|t| t.is_finished()))
    }

    /// What the search left once it has ended (`Some(None)` when it found
    /// no motion, its thread failed, or a clone of the engine took it);
    /// `None` while it runs. With `wait`, blocks until it ends.
    pub(super) fn ended(&self, wait: bool) -> Option<Option<RigidTrack>> {
        let Ok(mut slot) = self.thread.lock() else {
            return Some(None);
        };
        if !wait && slot.as_ref().is_some_and(|t| !t.is_finished()) {
            return None;
        }
        Some(slot.take().and_then(|t| t.join().ok().flatten()))
    }
}
