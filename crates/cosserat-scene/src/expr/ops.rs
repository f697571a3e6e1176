//! The operators of scene expressions and their syntax tree: one function per operator, shared by
//! constant folding and by evaluation, so both agree bit for bit.

use super::{MAX_PARAMS, MAX_VARIABLES};

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
    /// Every operator with a function-call name (all but `Neg`, written `-`).
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

    /// The operator's name as written in expressions (`clamp01` is internal, behind `ramp`).
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

    /// The value of the operator, shared by constant folding and evaluation so both agree bit for bit.
    #[inline(always)]
    pub(super) fn apply(self, a: f64) -> f64 {
        match self {
            Unary::Neg => -a,
            Unary::Not => truth(a == 0.0),
            Unary::Abs => a.abs(),
            Unary::Sgn => {
                if a > 0.0 {
                    1.0
                } else {
                    -1.0
                }
            }
            Unary::Sqrt => a.sqrt(),
            Unary::Exp => a.exp(),
            Unary::Ln => a.ln(),
            Unary::Sin => a.sin(),
            Unary::Cos => a.cos(),
            Unary::Tan => a.tan(),
            Unary::Asin => a.asin(),
            Unary::Acos => a.acos(),
            Unary::Atan => a.atan(),
            Unary::Sinh => a.sinh(),
            Unary::Cosh => a.cosh(),
            Unary::Tanh => a.tanh(),
            Unary::Floor => a.floor(),
            Unary::Ceil => a.ceil(),
            Unary::Round => a.round(),
            Unary::Clamp01 => a.clamp(0.0, 1.0),
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

    /// The value of the operator, shared by constant folding and evaluation so both agree bit for bit.
    #[inline(always)]
    pub(super) fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Binary::Add => a + b,
            Binary::Sub => a - b,
            Binary::Mul => a * b,
            Binary::Div => a / b,
            Binary::Pow => a.powf(b),
            Binary::Min => a.min(b),
            Binary::Max => a.max(b),
            Binary::Atan2 => a.atan2(b),
            Binary::Lt => truth(a < b),
            Binary::Le => truth(a <= b),
            Binary::Gt => truth(a > b),
            Binary::Ge => truth(a >= b),
            Binary::Eq => truth(a == b),
            Binary::Ne => truth(a != b),
            Binary::And => truth(a != 0.0 && b != 0.0),
            Binary::Or => truth(a != 0.0 || b != 0.0),
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

/// The syntax tree of an expression. `Param` only occurs in user-function bodies; `Call` refers to a
/// body in the function table of the compiled expression.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Node {
    Num(f64),
    Var(usize),
    Param(usize),
    Unary(Unary, Box<Node>),
    Binary(Binary, Box<Node>, Box<Node>),
    Call(usize, Vec<Node>),
}

impl Node {
    /// `op(a)`, folded if `a` is a finite number. A non-finite one stays in the tree: folding `!` or
    /// `sgn` of it would give a plain number and hide it from [`Node::non_finite_constant`].
    pub(super) fn unary(op: Unary, a: Node) -> Node {
        match a {
            Node::Num(v) if v.is_finite() => Node::Num(op.apply(v)),
            a => Node::Unary(op, Box::new(a)),
        }
    }

    /// `a op b`, folded if both are finite numbers. A non-finite one stays in the tree: a comparison
    /// of it folds to 0 or 1, which would hide `sqrt(-1) < 1` from [`Node::non_finite_constant`].
    pub(super) fn binary(op: Binary, a: Node, b: Node) -> Node {
        match (a, b) {
            (Node::Num(x), Node::Num(y)) if x.is_finite() && y.is_finite() => Node::Num(op.apply(x, y)),
            (a, b) => Node::Binary(op, Box::new(a), Box::new(b)),
        }
    }

    /// A call of function `index` of `functions`, folded if every argument is a finite number (as
    /// [`Node::binary`]).
    pub(super) fn call(index: usize, args: Vec<Node>, functions: &[Node]) -> Node {
        if args.iter().all(|a| matches!(a, Node::Num(v) if v.is_finite())) {
            let values: Vec<f64> = args
                .iter()
                .map(|a| match a {
                    Node::Num(v) => *v,
                    _ => unreachable!("all arguments are numbers"),
                })
                .collect();
            return Node::Num(functions[index].eval(&[], &values, functions));
        }
        Node::Call(index, args)
    }

    /// The value for scene variables `vars` and, inside a function body, its arguments `params`.
    pub(super) fn eval(&self, vars: &[f64], params: &[f64], functions: &[Node]) -> f64 {
        match self {
            Node::Num(v) => *v,
            Node::Var(i) => vars[*i],
            Node::Param(i) => params[*i],
            Node::Unary(op, a) => op.apply(a.eval(vars, params, functions)),
            Node::Binary(op, a, b) => op.apply(a.eval(vars, params, functions), b.eval(vars, params, functions)),
            Node::Call(f, args) => {
                let mut values = [0.0; MAX_PARAMS];
                for (value, arg) in values.iter_mut().zip(args) {
                    *value = arg.eval(vars, params, functions);
                }
                // Bodies use their parameters only, never the scene variables.
                functions[*f].eval(&[], &values[..args.len()], functions)
            }
        }
    }

    /// The number of operations one evaluation performs, a call counting its arguments and the cost
    /// of its body (`costs[f]` for function `f`), saturating.
    pub(super) fn cost(&self, costs: &[u64]) -> u64 {
        match self {
            Node::Num(_) | Node::Var(_) | Node::Param(_) => 1,
            Node::Unary(_, a) => a.cost(costs).saturating_add(1),
            Node::Binary(_, a, b) => a.cost(costs).saturating_add(b.cost(costs)).saturating_add(1),
            Node::Call(f, args) => args.iter().fold(costs[*f], |total, a| total.saturating_add(a.cost(costs))),
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
            Node::Call(_, args) => args.iter().for_each(|a| a.collect_variables(used)),
        }
    }

    /// The first non-finite folded constant, if any.
    pub(super) fn non_finite_constant(&self) -> Option<f64> {
        match self {
            Node::Num(v) => (!v.is_finite()).then_some(*v),
            Node::Var(_) | Node::Param(_) => None,
            Node::Unary(_, a) => a.non_finite_constant(),
            Node::Binary(_, a, b) => a.non_finite_constant().or_else(|| b.non_finite_constant()),
            Node::Call(_, args) => args.iter().find_map(Node::non_finite_constant),
        }
    }
}
