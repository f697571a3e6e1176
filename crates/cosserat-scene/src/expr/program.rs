//! The evaluator of compiled expressions: the syntax tree flattened into a postfix program run on a
//! small stack, one pass over a contiguous list of operations.

use super::MAX_PARAMS;
use super::ops::{Binary, Node, Unary};

/// One operation of a [`Program`].
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
    Num(f64),
    Var(usize),
    Param(usize),
    Unary(Unary),
    Binary(Binary),
    /// Call function `index` with the top `n_args` values as its arguments.
    Call {
        index: usize,
        n_args: usize,
    },
}

/// Stack depth evaluated without allocating; deeper programs (rare) use a vector.
const INLINE_STACK: usize = 32;

/// A postfix program: operands are pushed, operators replace their operands with the result.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Program {
    ops: Vec<Op>,
    depth: usize,
}

impl Program {
    /// The program of a syntax tree.
    pub(super) fn new(node: &Node) -> Self {
        let mut ops = Vec::new();
        let depth = emit(node, &mut ops);
        Self { ops, depth }
    }

    /// The value for scene variables `vars` and function arguments `params`; `functions` are the
    /// programs of the user functions that `Call` operations name.
    pub(super) fn eval(&self, vars: &[f64], params: &[f64], functions: &[Program]) -> f64 {
        match self.eval_with::<false>(vars, params, functions) {
            Ok(v) | Err(v) => v,
        }
    }

    /// The value as [`Program::eval`], or `Err` with the first value along the way (an operand,
    /// a function's result, the result itself) that is infinite or NaN. A comparison or a logical
    /// operator turns such an operand into a plain 0 or 1, so only the values along the way show that
    /// `x / 0 > 1` or `sqrt(x) < 1` at negative `x` has no meaningful answer.
    pub(super) fn eval_finite(&self, vars: &[f64], params: &[f64], functions: &[Program]) -> Result<f64, f64> {
        self.eval_with::<true>(vars, params, functions)
    }

    fn eval_with<const CHECK: bool>(&self, vars: &[f64], params: &[f64], functions: &[Program]) -> Result<f64, f64> {
        if self.depth <= INLINE_STACK {
            self.run::<CHECK>(&mut [0.0; INLINE_STACK], vars, params, functions)
        } else {
            self.run::<CHECK>(&mut vec![0.0; self.depth], vars, params, functions)
        }
    }

    /// Runs the operations; with `CHECK`, stops at the first value that is not finite.
    fn run<const CHECK: bool>(
        &self,
        stack: &mut [f64],
        vars: &[f64],
        params: &[f64],
        functions: &[Program],
    ) -> Result<f64, f64> {
        let mut top = 0;
        for op in &self.ops {
            match *op {
                Op::Num(v) => {
                    stack[top] = v;
                    top += 1;
                }
                Op::Var(i) => {
                    stack[top] = vars[i];
                    top += 1;
                }
                Op::Param(i) => {
                    stack[top] = params[i];
                    top += 1;
                }
                Op::Unary(op) => stack[top - 1] = op.apply(stack[top - 1]),
                Op::Binary(op) => {
                    top -= 1;
                    stack[top - 1] = op.apply(stack[top - 1], stack[top]);
                }
                Op::Call { index, n_args } => {
                    let mut args = [0.0; MAX_PARAMS];
                    top -= n_args;
                    args[..n_args].copy_from_slice(&stack[top..top + n_args]);
                    // Bodies use their parameters only, never the scene variables.
                    stack[top] = functions[index].eval_with::<CHECK>(&[], &args[..n_args], functions)?;
                    top += 1;
                }
            }
            if CHECK && !stack[top - 1].is_finite() {
                return Err(stack[top - 1]);
            }
        }
        Ok(stack[0])
    }
}

/// Appends the postfix form of `node`; returns the stack depth it needs.
fn emit(node: &Node, ops: &mut Vec<Op>) -> usize {
    match node {
        Node::Num(v) => {
            ops.push(Op::Num(*v));
            1
        }
        Node::Var(i) => {
            ops.push(Op::Var(*i));
            1
        }
        Node::Param(i) => {
            ops.push(Op::Param(*i));
            1
        }
        Node::Unary(op, a) => {
            let depth = emit(a, ops);
            ops.push(Op::Unary(*op));
            depth
        }
        Node::Binary(op, a, b) => {
            let depth = emit(a, ops).max(1 + emit(b, ops));
            ops.push(Op::Binary(*op));
            depth
        }
        Node::Call(index, args) => {
            let depth = args.iter().enumerate().map(|(k, a)| k + emit(a, ops)).max().unwrap_or(0);
            ops.push(Op::Call {
                index: *index,
                n_args: args.len(),
            });
            depth.max(1)
        }
    }
}
