//! The search for `mu` during a run ([`Layers::adapt_mu`](crate::settings::Layers::adapt_mu)):
//! a run in pieces of one frame, and at the end of each the work of the frame weighed
//! by the [`MuSearcher`], which may move `mu` ([`Simulator::rescale_mu`]).

use super::Simulator;
use crate::design::MuSearcher;
use crate::settings::AdaptiveMu;
use crate::summary::MuSearchSummary;
use crate::{Model, SimError};

/// A search in a run: the searcher, the frames' clock and the work counted so far.
#[derive(Clone, Debug)]
pub(super) struct SearchRun {
    searcher: MuSearcher,
    frame: f64,
    origin: f64,
    /// Frames ended so far.
    frames: u64,
    work_before: u64,
}

impl SearchRun {
    pub(super) fn new(how: AdaptiveMu, origin: f64) -> Self {
        Self {
            searcher: MuSearcher::new(how),
            frame: how.frame,
            origin,
            frames: 0,
            work_before: 0,
        }
    }

    /// The end of the frame the run is in.
    pub(super) fn next_end(&self) -> f64 {
        self.origin + (self.frames + 1) as f64 * self.frame
    }

    /// The end of the frame the run is in as a run to `target` meets it: `target`
    /// itself when the two differ by rounding only (a caller's cuts that sum one frame
    /// after another drift from `origin + k frame` by a few units of the last place a
    /// frame), so that no piece of a few ulps is stepped.
    pub(super) fn end_toward(&self, target: f64) -> f64 {
        let end = self.next_end();
        if (end - target).abs() <= 1e-9 * self.frame {
            target
        } else {
            end
        }
    }
}

impl<M: Model> Simulator<M> {
    /// The work a search weighs: evaluations of `f` and factorisations of `J_s`.
    fn search_work(&self) -> u64 {
        self.stats.rhs_evals + self.solver_stats().factorisations
    }

    /// At the end of a frame: the search weighs the frame's work and may move `mu`.
    /// A move the simulator refuses (the state would leave the layer at the new `mu`)
    /// leaves `mu` where it was, and the search measures again from there.
    pub(super) fn end_search_frame(&mut self) -> Result<(), SimError> {
        let work = self.search_work();
        let Some(search) = self.search.as_mut() else {
            return Ok(());
        };
        search.frames += 1;
        let frame_work = work - search.work_before;
        search.work_before = work;
        // A frame that lost a layer is not a cost to learn from: its low work may be
        // the layer given up. The search stays where it is from then on.
        if self.stats.loss.lost() {
            return Ok(());
        }
        // The reaching phase is not the cost of the run, and a larger mu (its gains
        // scaled down with it) would slow the reaching itself.
        if self.stats.reaching_time.is_none() {
            return Ok(());
        }
        let Some(factor) = search.searcher.after_frame(frame_work) else {
            return Ok(());
        };
        if !self.rescale_mu(factor)? {
            if let Some(search) = self.search.as_mut() {
                search.searcher.refused(factor);
            }
        }
        Ok(())
    }

    /// Start the search of the settings (if any) with the run.
    pub(super) fn start_search(&mut self) {
        self.search = self
            .set
            .layers
            .adapt_mu
            .map(|how| SearchRun::new(how, self.set.window.t_start));
    }

    /// With a search of `mu` ([`Layers::adapt_mu`](crate::settings::Layers::adapt_mu)),
    /// what it did so far (what [`Summary::mu_search`](crate::Summary::mu_search) will
    /// say).
    pub fn mu_search(&self) -> Option<MuSearchSummary> {
        self.search.as_ref().map(|s| {
            let (moves, refused) = s.searcher.moves();
            MuSearchSummary {
                scale: s.searcher.scale(),
                moves,
                refused,
                surges: s.searcher.surges(),
                frames: s.frames,
            }
        })
    }
}
