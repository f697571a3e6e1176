//! The operators of scene expressions and their syntax tree: one function per operator, shared by
//! constant folding and by the exmex operator table, and the fully parenthesised text handed to exmex.

use super::MAX_VARIABLES;
use exmex::{BinOp, MakeOperators, Operator};
use std::fmt::Write as _;

/// Operators of one argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Unary {
    Neg,
    Not,
    Abs,
    Sgn,
    Sqrt,
    Exp,
    Ln,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Floor,
    Ceil,
    Round,
    Clamp01,
}

impl Unary {
    /// Every operator with a function-call name (all but `Neg`, which exmex provides with `-`).
    pub(super) const NAMED: [Unary; 19] = [
        Unary::Not,
        Unary::Abs,
        Unary::Sgn,
        Unary::Sqrt,
        Unary::Exp,
        Unary::Ln,
        Unary::Sin,
        Unary::Cos,
        Unary::Tan,
        Unary::Asin,
        Unary::Acos,
        Unary::Atan,
        Unary::Sinh,
        Unary::Cosh,
        Unary::Tanh,
        Unary::Floor,
        Unary::Ceil,
        Unary::Round,
        Unary::Clamp01,
    ];

    /// The representation in the text handed to exmex.
    pub(super) fn repr(self) -> &'static str {
        match self {
            Unary::Neg => "-",
            Unary::Not => "!",
            Unary::Abs => "abs",
            Unary::Sgn => "sgn",
            Unary::Sqrt => "sqrt",
            Unary::Exp => "exp",
            Unary::Ln => "ln",
            Unary::Sin => "sin",
            Unary::Cos => "cos",
            Unary::Tan => "tan",
            Unary::Asin => "asin",
            Unary::Acos => "acos",
            Unary::Atan => "atan",
            Unary::Sinh => "sinh",
            Unary::Cosh => "cosh",
            Unary::Tanh => "tanh",
            Unary::Floor => "floor",
            Unary::Ceil => "ceil",
            Unary::Round => "round",
            Unary::Clamp01 => "clamp01",
        }
    }

    /// The built-in function of this name, if any.
    pub(super) fn from_name(name: &str) -> Option<Self> {
        match name {
            "sign" => Some(Unary::Sgn),
            "log" => Some(Unary::Ln),
            "clamp01" | "!" => None,
            _ => Self::NAMED.into_iter().find(|u| u.repr() == name),
        }
    }

    /// The function, shared by constant folding and the exmex operator table so both agree bit for bit.
    pub(super) fn function(self) -> fn(f64) -> f64 {
        match self {
            Unary::Neg => |a| -a,
            Unary::Not => |a| truth(a == 0.0),
            Unary::Abs => f64::abs,
            Unary::Sgn => |a| if a > 0.0 { 1.0 } else { -1.0 },
            Unary::Sqrt => f64::sqrt,
            Unary::Exp => f64::exp,
            Unary::Ln => f64::ln,
            Unary::Sin => f64::sin,
            Unary::Cos => f64::cos,
            Unary::Tan => f64::tan,
            Unary::Asin => f64::asin,
            Unary::Acos => f64::acos,
            Unary::Atan => f64::atan,
            Unary::Sinh => f64::sinh,
            Unary::Cosh => f64::cosh,
            Unary::Tanh => f64::tanh,
            Unary::Floor => f64::floor,
            Unary::Ceil => f64::ceil,
            Unary::Round => f64::round,
            Unary::Clamp01 => |a| a.clamp(0.0, 1.0),
        }
    }
}

/// Operators of two arguments.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Binary {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Min,
    Max,
    Atan2,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
}

impl Binary {
    pub(super) const ALL: [Binary; 16] = [
        Binary::Add,
        Binary::Sub,
        Binary::Mul,
        Binary::Div,
        Binary::Pow,
        Binary::Min,
        Binary::Max,
        Binary::Atan2,
        Binary::Lt,
        Binary::Le,
        Binary::Gt,
        Binary::Ge,
        Binary::Eq,
        Binary::Ne,
        Binary::And,
        Binary::Or,
    ];

    pub(super) fn repr(self) -> &'static str {
        match self {
            Binary::Add => "+",
            Binary::Sub => "-",
            Binary::Mul => "*",
            Binary::Div => "/",
            Binary::Pow => "^",
            Binary::Min => "min",
            Binary::Max => "max",
            Binary::Atan2 => "atan2",
            Binary::Lt => "<",
            Binary::Le => "<=",
            Binary::Gt => ">",
            Binary::Ge => ">=",
            Binary::Eq => "==",
            Binary::Ne => "!=",
            Binary::And => "&&",
            Binary::Or => "||",
        }
    }

    pub(super) fn function(self) -> fn(f64, f64) -> f64 {
        match self {
            Binary::Add => |a, b| a + b,
            Binary::Sub => |a, b| a - b,
            Binary::Mul => |a, b| a * b,
            Binary::Div => |a, b| a / b,
            Binary::Pow => f64::powf,
            Binary::Min => f64::min,
            Binary::Max => f64::max,
            Binary::Atan2 => f64::atan2,
            Binary::Lt => |a, b| truth(a < b),
            Binary::Le => |a, b| truth(a <= b),
            Binary::Gt => |a, b| truth(a > b),
            Binary::Ge => |a, b| truth(a >= b),
            Binary::Eq => |a, b| truth(a == b),
            Binary::Ne => |a, b| truth(a != b),
            Binary::And => |a, b| truth(a != 0.0 && b != 0.0),
            Binary::Or => |a, b| truth(a != 0.0 || b != 0.0),
        }
    }

    /// Precedence of an infix operator (higher binds tighter); `^` is handled separately.
    pub(super) fn infix_precedence(self) -> u8 {
        match self {
            Binary::Or => 1,
            Binary::And => 2,
            Binary::Lt | Binary::Le | Binary::Gt | Binary::Ge | Binary::Eq | Binary::Ne => 3,
            Binary::Add | Binary::Sub => 4,
            Binary::Mul | Binary::Div => 5,
            Binary::Pow | Binary::Min | Binary::Max | Binary::Atan2 => 6,
        }
    }
}

pub(super) fn truth(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

/// The operator table of the compiled expressions. The text given to exmex is fully parenthesised,
/// so every parenthesis group holds one operator and the priorities below never decide anything.
#[derive(Debug, Clone)]
pub(super) struct SceneOps;

impl MakeOperators<f64> for SceneOps {
    fn make<'a>() -> Vec<Operator<'a, f64>> {
        let mut ops = Vec::with_capacity(40);
        for op in Binary::ALL {
            let bin = BinOp {
                apply: op.function(),
                prio: 0,
                is_commutative: false,
            };
            if op == Binary::Sub {
                ops.push(Operator::make_bin_unary(op.repr(), bin, Unary::Neg.function()));
            } else {
                ops.push(Operator::make_bin(op.repr(), bin));
            }
        }
        for op in Unary::NAMED {
            ops.push(Operator::make_unary(op.repr(), op.function()));
        }
        ops
    }
}

/// The syntax tree of an expression. `Param` only occurs in user-function bodies.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Node {
    Num(f64),
    Var(usize),
    Param(usize),
    Unary(Unary, Box<Node>),
    Binary(Binary, Box<Node>, Box<Node>),
}

impl Node {
    /// `op(a)`, folded if `a` is a number.
    pub(super) fn unary(op: Unary, a: Node) -> Node {
        match a {
            Node::Num(v) => Node::Num(op.function()(v)),
            a => Node::Unary(op, Box::new(a)),
        }
    }

    /// `a op b`, folded if both are numbers.
    pub(super) fn binary(op: Binary, a: Node, b: Node) -> Node {
        match (a, b) {
            (Node::Num(x), Node::Num(y)) => Node::Num(op.function()(x, y)),
            (a, b) => Node::Binary(op, Box::new(a), Box::new(b)),
        }
    }

    /// The node with every `Param(i)` replaced by `args[i]` (and constants folded again).
    pub(super) fn substitute(&self, args: &[Node]) -> Node {
        match self {
            Node::Param(i) => args[*i].clone(),
            Node::Num(_) | Node::Var(_) => self.clone(),
            Node::Unary(op, a) => Node::unary(*op, a.substitute(args)),
            Node::Binary(op, a, b) => Node::binary(*op, a.substitute(args), b.substitute(args)),
        }
    }

    /// Marks the variables used.
    pub(super) fn collect_variables(&self, used: &mut [bool; MAX_VARIABLES]) {
        match self {
            Node::Var(i) => used[*i] = true,
            Node::Num(_) | Node::Param(_) => {}
            Node::Unary(_, a) => a.collect_variables(used),
            Node::Binary(_, a, b) => {
                a.collect_variables(used);
                b.collect_variables(used);
            }
        }
    }

    /// Writes the fully parenthesised exmex form. Numbers are finite (checked before).
    pub(super) fn emit(&self, out: &mut String) {
        match self {
            Node::Num(v) => {
                // `{}` prints the shortest decimal that round-trips, never in exponent form.
                if *v == 0.0 {
                    out.push('0');
                } else if *v > 0.0 {
                    let _ = write!(out, "{v}");
                } else {
                    let _ = write!(out, "(-{})", -v);
                }
            }
            Node::Var(i) => {
                let _ = write!(out, "v{i}");
            }
            Node::Param(_) => unreachable!("parameters are substituted before emission"),
            Node::Unary(Unary::Neg, a) => {
                out.push_str("(-(");
                a.emit(out);
                out.push_str("))");
            }
            Node::Unary(op, a) => {
                out.push_str(op.repr());
                out.push_str("((");
                a.emit(out);
                out.push_str("))");
            }
            Node::Binary(op, a, b) => {
                out.push_str("((");
                a.emit(out);
                out.push(')');
                out.push_str(op.repr());
                out.push('(');
                b.emit(out);
                out.push_str("))");
            }
        }
    }

    /// The first non-finite folded constant, if any.
    pub(super) fn non_finite_constant(&self) -> Option<f64> {
        match self {
            Node::Num(v) => (!v.is_finite()).then_some(*v),
            Node::Var(_) | Node::Param(_) => None,
            Node::Unary(_, a) => a.non_finite_constant(),
            Node::Binary(_, a, b) => a.non_finite_constant().or_else(|| b.non_finite_constant()),
        }
    }
}
