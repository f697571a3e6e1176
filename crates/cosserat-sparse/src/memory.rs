//! Buffers whose pages are mapped when they are allocated.
//!
//! Large allocations come from the operating system as lazily mapped zero pages: the first write to
//! each page faults, and the kernel clears it then. Left lazy, the first numerical factorisation pays
//! for every page of the values it copies and of faer's workspace, and the first assembly for those
//! of the Hessian values, which on large meshes nearly doubles the first factorisation's time. The
//! buffers that the assembly and the factorisations reuse are therefore written once when they are
//! set up, together with the analysis that sizes them.

use faer::dyn_stack::{MemBuffer, StackReq};

/// A zeroed vector whose memory is written now (`vec![0.0; n]` would get lazily mapped zero pages).
pub fn mapped_zeros(len: usize) -> Vec<f64> {
    let mut v = Vec::with_capacity(len);
    v.resize(len, 0.0);
    v
}

/// A workspace of `req` whose memory is written now; `None` if it cannot be allocated.
pub fn mapped_workspace(req: StackReq) -> Option<MemBuffer> {
    let mut mem = MemBuffer::try_new(req).ok()?;
    mem.fill(std::mem::MaybeUninit::new(0));
    Some(mem)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffers_have_the_requested_sizes_and_zeros() {
        let v = mapped_zeros(1 << 20);
        assert_eq!(v.len(), 1 << 20);
        assert!(v.iter().all(|&x| x == 0.0));
        let mem = mapped_workspace(StackReq::new::<f64>(1 << 18)).expect("a 2 MB workspace");
        assert!(mem.len() >= 8 << 18);
    }
}
