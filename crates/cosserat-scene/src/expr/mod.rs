//! Scene expressions: the small formula language of scripted angles, loads, rest fields and region
//! predicates, compiled once into fast evaluators.
//!
//! A scene writes a scripted quantity either as a plain number or as a string such as
//! `"2*pi*t"`, `"50*ramp(t, 0, 1)"` or `"4*pi*ramp(t, 0, 2.5)*sgn(x)"`. [`ExprContext::compile`]
//! parses the string with standard precedence, checks every name, folds constants, and keeps the
//! syntax tree, which [`Expr::eval`] walks. User functions are parsed once per compiled expression
//! and called, not copied into the tree, so helpers that call each other stay small; the operations of
//! one evaluation are counted at compile time and bounded ([`MAX_OPERATIONS`]), so a chain of helpers
//! that each call the next twice is refused instead of running for ever.
//!
//! Why not a crate: the expression crates we tried (exmex among them) have no functions of three
//! arguments (`ramp`, `clamp`), bind unary minus tighter than `^` (`-x^2` would be `x²`), read `1e-9`
//! as `1·e − 9`, or report errors without a column; the parser here handles those, and evaluating its
//! tree is a few lines. An evaluation costs tens to a few hundred nanoseconds for the paper's formulas
//! (`examples/expr_eval.rs` measures them), small beside a time step.
//!
//! Syntax (highest precedence last):
//! - `a || b`, `a && b` (logical; operands are true when non-zero; results are 1 or 0);
//! - `a < b`, `a <= b`, `a > b`, `a >= b`, `a == b`, `a != b` (1 if true, 0 if false);
//! - `a + b`, `a - b`; `a * b`, `a / b` (left-associative);
//! - unary `-a`, `+a`, `!a`;
//! - `a ^ b` (power, right-associative, binds tighter than unary minus: `-x^2 = -(x²)`, `x^-2` works);
//! - numbers (`3`, `0.5`, `.5`, `1e-9`, `2.5E+3`), names and calls `f(a, b, …)`, parentheses.
//!
//! Built-in functions: `abs`, `sqrt`, `exp`, `ln` (= `log`), `sin`, `cos`, `tan`, `asin`, `acos`,
//! `atan`, `sinh`, `cosh`, `tanh`, `floor`, `ceil`, `round`; `sgn(x)` = `sign(x)` (+1 for `x > 0`, −1
//! otherwise, so `sgn(0) = −1` as the curvature-modes scene needs); `min(a, b, …)` and `max(a, b, …)`
//! (two or more arguments); `atan2(y, x)`; `clamp(x, lo, hi)` = `min(max(x, lo), hi)`;
//! `ramp(t, t0, t1)` = `clamp((t − t0)/(t1 − t0), 0, 1)`. Constants: `pi`, `e`.
//!
//! User functions ([`ExprContext::define`]) have up to [`MAX_PARAMS`] named parameters and a body that
//! may use those parameters, constants, built-ins and other user functions (not the scene variables,
//! and not recursively). A call with constant arguments is folded to its value. The Lotus scene, for
//! example, defines its profile `p(u) = −0.2314286 + 10.89881u − 14.28571u² + 4.427083u³` once and
//! calls it twice.

mod ops;
mod parse;
mod program;

use crate::error::{ExprError, Num};
use crate::spec::{FieldFunction, TimeFunction};
use nalgebra::Vector3;
use ops::Node;
use parse::{FunctionTable, Parser, Scope, is_builtin_function, is_identifier};
use program::Program;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The most variables an expression can have (`x, y, z, t`).
pub const MAX_VARIABLES: usize = 4;

/// Names that cannot be used as variables, parameters or user functions.
const CONSTANTS: [(&str, f64); 2] = [("pi", std::f64::consts::PI), ("e", std::f64::consts::E)];

/// How deep user functions may call each other before the call is reported as recursive.
const MAX_CALL_DEPTH: usize = 32;

/// How deeply parentheses, calls and unary operators may nest (bounds the recursion of the parser).
const MAX_NESTING: usize = 100;

/// The most parameters a user function may have.
pub const MAX_PARAMS: usize = 8;

/// The most operations one evaluation of an expression may perform, calls of user functions
/// included: far above any formula of a scene, far below one that would slow a run down.
pub const MAX_OPERATIONS: u64 = 100_000;

/// A user function: parameter names and body text.
#[derive(Debug, Clone, PartialEq)]
struct UserFunction {
    params: Vec<String>,
    body: String,
}

/// Named user functions available to expressions.
///
/// Build one per scene with [`ExprContext::define`], then compile every expression of the scene with
/// [`ExprContext::compile`] (or the typed helpers [`ExprContext::time_function`],
/// [`ExprContext::field_function`] and [`ExprContext::predicate`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExprContext {
    functions: BTreeMap<String, UserFunction>,
}

impl ExprContext {
    /// A context without user functions.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a user function `name(params…) = body`. The body is checked when an expression calls the
    /// function, and by [`ExprContext::check_functions`].
    ///
    /// # Errors
    /// [`ExprError::Definition`] for a name or parameter that is not an identifier, clashes with a
    /// built-in function, a constant or a scene variable (`x`, `y`, `z`, `t`), or is defined twice.
    pub fn define(&mut self, name: &str, params: &[String], body: &str) -> Result<(), ExprError> {
        let reserved = |n: &str| {
            is_builtin_function(n) || CONSTANTS.iter().any(|(c, _)| *c == n) || matches!(n, "x" | "y" | "z" | "t")
        };
        let definition_error = |reason: String| ExprError::Definition {
            name: name.to_string(),
            reason,
        };
        if !is_identifier(name) {
            return Err(definition_error(
                "a function name must be an identifier (letters, digits, `_`)".into(),
            ));
        }
        if reserved(name) {
            return Err(definition_error(
                "the name is reserved (a built-in function, constant or variable)".into(),
            ));
        }
        if self.functions.contains_key(name) {
            return Err(definition_error("defined twice".into()));
        }
        if params.len() > MAX_PARAMS {
            return Err(definition_error(format!(
                "has {} parameters; at most {MAX_PARAMS} are allowed",
                params.len()
            )));
        }
        for (i, p) in params.iter().enumerate() {
            if !is_identifier(p) || is_builtin_function(p) || CONSTANTS.iter().any(|(c, _)| c == p) {
                return Err(definition_error(format!("parameter `{p}` is not a usable name")));
            }
            if params[..i].contains(p) {
                return Err(definition_error(format!("parameter `{p}` appears twice")));
            }
        }
        self.functions.insert(
            name.to_string(),
            UserFunction {
                params: params.to_vec(),
                body: body.to_string(),
            },
        );
        Ok(())
    }

    /// Parses every user function body once, so that errors show up even for unused functions.
    ///
    /// # Errors
    /// The first function whose body does not parse, as [`ExprError::Definition`] wrapping the reason.
    pub fn check_functions(&self) -> Result<(), ExprError> {
        for (name, function) in &self.functions {
            let table = RefCell::new(FunctionTable::default());
            let body = self.parse_body(name, function, &[], &table)?;
            let cost = body.cost(&table.borrow().costs);
            if cost > MAX_OPERATIONS {
                return Err(ExprError::Definition {
                    name: name.clone(),
                    reason: too_costly(cost),
                });
            }
        }
        Ok(())
    }

    fn parse_body<'a>(
        &'a self,
        name: &'a str,
        function: &'a UserFunction,
        stack: &[&'a str],
        table: &'a RefCell<FunctionTable>,
    ) -> Result<Node, ExprError> {
        let wrap = |e: ExprError| ExprError::Definition {
            name: name.to_string(),
            reason: e.to_string(),
        };
        let mut parser = Parser::new(self, table, &function.body).map_err(wrap)?;
        let mut stack: Vec<&str> = stack.to_vec();
        stack.push(name);
        let mut scope = Scope {
            variables: &[],
            params: &function.params,
            stack,
        };
        let body = parser.parse_all(&mut scope).map_err(|e| match e {
            // Errors from nested definitions are already wrapped.
            e @ ExprError::Definition { .. } => e,
            e => wrap(e),
        })?;
        if let Some(value) = body.non_finite_constant() {
            return Err(wrap(ExprError::NonFinite {
                expression: function.body.clone(),
                value,
                at: "a constant part of the body".into(),
            }));
        }
        Ok(body)
    }

    /// Compiles `text` as a function of the named `variables` (at most [`MAX_VARIABLES`]), which are
    /// passed to [`Expr::eval`] in the same order.
    ///
    /// # Errors
    /// [`ExprError::Parse`] (with the column), [`ExprError::UnknownVariable`],
    /// [`ExprError::UnknownFunction`], [`ExprError::Definition`] for a broken user function,
    /// [`ExprError::NonFinite`] when a constant part is infinite or NaN (e.g. `1/0`), and
    /// [`ExprError::TooManyVariables`].
    ///
    /// # Example
    /// ```
    /// use cosserat_scene::expr::ExprContext;
    /// let ctx = ExprContext::new();
    /// let e = ctx.compile("2*ramp(t, 0, 4) - x^2", &["x", "t"])?;
    /// assert_eq!(e.eval(&[3.0, 1.0]), 2.0 * 0.25 - 9.0);
    /// # Ok::<(), cosserat_scene::error::ExprError>(())
    /// ```
    pub fn compile(&self, text: &str, variables: &[&str]) -> Result<Expr, ExprError> {
        if variables.len() > MAX_VARIABLES {
            return Err(ExprError::TooManyVariables {
                expression: text.to_string(),
                max: MAX_VARIABLES,
            });
        }
        let table = RefCell::new(FunctionTable::default());
        let mut parser = Parser::new(self, &table, text)?;
        let mut scope = Scope {
            variables,
            params: &[],
            stack: Vec::new(),
        };
        let root = parser.parse_all(&mut scope)?;
        drop(parser);
        let table = table.into_inner();
        if let Some(value) = root.non_finite_constant() {
            return Err(ExprError::NonFinite {
                expression: text.to_string(),
                value,
                at: "a constant part of the expression".into(),
            });
        }
        let cost = root.cost(&table.costs);
        if cost > MAX_OPERATIONS {
            return Err(ExprError::Parse {
                expression: text.to_string(),
                column: 1,
                reason: too_costly(cost),
            });
        }
        let mut used = [false; MAX_VARIABLES];
        root.collect_variables(&mut used);
        Ok(Expr {
            text: text.to_string(),
            used,
            constant: matches!(root, Node::Num(_)),
            program: Program::new(&root),
            functions: table.bodies.iter().map(Program::new).collect(),
        })
    }

    /// Compiles a function of time `t`.
    ///
    /// # Errors
    /// As [`ExprContext::compile`].
    pub fn time_function(&self, text: &str) -> Result<TimeFunction, ExprError> {
        let expr = self.compile(text, &["t"])?;
        Ok(TimeFunction::new(text, move |t| expr.eval(&[t])))
    }

    /// Compiles a function of the rest position `x, y, z` and time `t`.
    ///
    /// # Errors
    /// As [`ExprContext::compile`].
    pub fn field_function(&self, text: &str) -> Result<FieldFunction, ExprError> {
        let expr = self.compile(text, &["x", "y", "z", "t"])?;
        let time_dependent = expr.uses(3);
        Ok(FieldFunction::new(text, time_dependent, move |p: &Vector3<f64>, t| {
            expr.eval(&[p.x, p.y, p.z, t])
        }))
    }

    /// Compiles a predicate of the position `x, y, z` (see [`Predicate`]).
    ///
    /// # Errors
    /// As [`ExprContext::compile`].
    pub fn predicate(&self, text: &str) -> Result<Predicate, ExprError> {
        Ok(Predicate {
            expr: self.compile(text, &["x", "y", "z"])?,
        })
    }
}

/// The reason for refusing an expression that costs `cost` operations per evaluation.
fn too_costly(cost: u64) -> String {
    format!(
        "one evaluation would take {cost} operations (user functions calling each other), more than the \
         limit of {MAX_OPERATIONS}"
    )
}

/// A compiled expression. Cheap to evaluate from many threads (`Send + Sync`, no interior state).
#[derive(Clone)]
pub struct Expr {
    text: String,
    used: [bool; MAX_VARIABLES],
    constant: bool,
    program: Program,
    /// The bodies of the user functions the expression calls.
    functions: Arc<[Program]>,
}

impl std::fmt::Debug for Expr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Expr({})", self.text)
    }
}

impl Expr {
    /// The value for the given variables (in the order given to [`ExprContext::compile`]).
    ///
    /// # Panics
    /// If `vars` is shorter than the variable list the expression was compiled with.
    #[inline]
    pub fn eval(&self, vars: &[f64]) -> f64 {
        self.program.eval(vars, &[], &self.functions)
    }

    /// The value as [`Expr::eval`], or `Err` with the first value along the way that is infinite or
    /// NaN (see [`Predicate::test`] for why the result alone does not tell).
    pub fn eval_finite(&self, vars: &[f64]) -> Result<f64, f64> {
        self.program.eval_finite(vars, &[], &self.functions)
    }

    /// The source text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// Whether variable number `i` (in compile order) occurs in the expression.
    pub fn uses(&self, i: usize) -> bool {
        self.used.get(i).copied().unwrap_or(false)
    }

    /// Whether the expression folded to a constant.
    pub fn is_constant(&self) -> bool {
        self.constant
    }
}

/// A compiled region predicate of `x, y, z`: it must evaluate to 1 (true, the node is selected) or 0
/// (false) — use comparisons and `&&`/`||`, e.g. `"x <= -0.05 + 1e-9"` or `"abs(y) < 0.01 && z >= 0"`.
#[derive(Debug, Clone)]
pub struct Predicate {
    expr: Expr,
}

impl Predicate {
    /// Whether the point satisfies the predicate.
    ///
    /// Every value along the way must be finite: a comparison turns an infinite or NaN operand into a
    /// plain 0 or 1, so `x / 0 > 1` would otherwise select the nodes at positive `x` without a word.
    ///
    /// # Errors
    /// [`ExprError::NonFiniteOperand`] if a value along the way is infinite or NaN (a division by
    /// zero, `sqrt` or `ln` of a negative number), [`ExprError::NotBoolean`] if the value is neither 0
    /// nor 1 (e.g. `"x + 0.05"`).
    pub fn test(&self, p: &Vector3<f64>) -> Result<bool, ExprError> {
        let at = || format!("({}, {}, {})", Num(p.x), Num(p.y), Num(p.z));
        let v = self
            .expr
            .eval_finite(&[p.x, p.y, p.z])
            .map_err(|value| ExprError::NonFiniteOperand {
                expression: self.expr.text.clone(),
                value,
                at: at(),
            })?;
        if v == 1.0 {
            Ok(true)
        } else if v == 0.0 {
            Ok(false)
        } else {
            Err(ExprError::NotBoolean {
                expression: self.expr.text.clone(),
                value: v,
                at: at(),
            })
        }
    }

    /// The source text.
    pub fn text(&self) -> &str {
        self.expr.text()
    }
}

#[cfg(test)]
mod tests {
    use super::ops::{Binary, Unary};
    use super::parse::{TokenKind, tokenize};
    use super::*;

    #[test]
    fn constants_fold() {
        let ctx = ExprContext::new();
        assert!(ctx.compile("ramp(2, 0, 4) * 3", &[]).unwrap().is_constant());
        let expected = Node::Binary(
            Binary::Mul,
            Box::new(Node::Binary(
                Binary::Mul,
                Box::new(Node::Var(0)),
                Box::new(Node::Num(5.0)),
            )),
            Box::new(Node::Num(std::f64::consts::PI)),
        );
        assert_eq!(
            ctx.compile("x * (2 + 3) * pi", &["x"]).unwrap().program,
            Program::new(&expected)
        );
        let mut ctx = ExprContext::new();
        ctx.define("sq", &["u".into()], "u*u").unwrap();
        assert!(ctx.compile("sq(3) + 1", &[]).unwrap().is_constant());
        assert!(!ctx.compile("sq(t)", &["t"]).unwrap().is_constant());
    }

    #[test]
    fn tokenizer_reads_scientific_numbers_and_two_character_operators() {
        let kinds: Vec<TokenKind> = tokenize("1e-9<=.5E+2**2").unwrap().into_iter().map(|t| t.kind).collect();
        assert_eq!(
            kinds,
            [
                TokenKind::Num(1e-9),
                TokenKind::Op("<="),
                TokenKind::Num(50.0),
                TokenKind::Op("^"),
                TokenKind::Num(2.0),
                TokenKind::End
            ]
        );
    }

    #[test]
    fn folding_and_evaluation_agree_on_every_operator() {
        // Each operator once folded at compile time (both arguments constant) and once evaluated (one
        // argument a variable): the same bits; constants that fold to a non-finite value are refused.
        let ctx = ExprContext::new();
        let samples = [-2.5, -1.0, 0.0, 0.3, 1.0, 2.0];
        let check = |constant: String, variable: String, a: f64| {
            let evaluated = ctx.compile(&variable, &["v"]).unwrap().eval(&[a]);
            match ctx.compile(&constant, &[]) {
                Ok(folded) => {
                    let folded = folded.eval(&[]);
                    assert!(
                        folded.is_finite() && folded.to_bits() == evaluated.to_bits(),
                        "{constant}: folded {folded}, evaluated {evaluated}"
                    );
                }
                Err(ExprError::NonFinite { .. }) => {
                    assert!(!evaluated.is_finite(), "{constant}: refused, evaluated {evaluated}")
                }
                Err(e) => panic!("{constant}: {e}"),
            }
        };
        for op in Binary::ALL {
            let call = matches!(op, Binary::Min | Binary::Max | Binary::Atan2);
            for &a in &samples {
                for &b in &samples {
                    let text = |x: String| {
                        if call {
                            format!("{}({x}, {b})", op.repr())
                        } else {
                            format!("({x} {} {b})", op.repr())
                        }
                    };
                    check(text(format!("({a})")), text("v".into()), a);
                }
            }
        }
        for op in Unary::NAMED {
            if op == Unary::Not || op == Unary::Clamp01 {
                continue;
            }
            for &a in &samples {
                check(format!("{}({a})", op.repr()), format!("{}(v)", op.repr()), a);
            }
        }
    }
}
