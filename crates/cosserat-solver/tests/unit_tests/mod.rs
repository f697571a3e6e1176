//! Test modules mirroring `src/`, plus toy problems; the sparse test matrices come from
//! `cosserat_sparse::testing`.

use cosserat_sparse::testing as fixtures;

mod continuation;
mod convergence;
mod error;
mod newton;
mod newton_cg;
mod newton_relaxed;
mod toy;
