//! Tokenizer and recursive-descent parser of scene expressions: standard precedence, named checks
//! of every variable and function, user functions parsed once into a table and called, errors with
//! the column.

use super::ops::{Binary, Node, Unary};
use super::{CONSTANTS, ExprContext, MAX_CALL_DEPTH, MAX_NESTING};
use crate::error::ExprError;
use std::cell::RefCell;

/// The user functions one compiled expression calls: each body parsed once, with the cost of one
/// evaluation of it.
#[derive(Debug, Default)]
pub(super) struct FunctionTable {
    pub(super) names: Vec<String>,
    pub(super) bodies: Vec<Node>,
    pub(super) costs: Vec<u64>,
}

/// A token with its 1-based character column.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Token {
    pub(super) kind: TokenKind,
    pub(super) column: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum TokenKind {
    Num(f64),
    Ident(String),
    Op(&'static str),
    Open,
    Close,
    Comma,
    End,
}

pub(super) fn tokenize(text: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    let error = |column: usize, reason: String| ExprError::Parse {
        expression: text.to_string(),
        column,
        reason,
    };
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit())) {
            let start = i;
            i = number_end(&chars, start)
                .ok_or_else(|| error(column, "a number's exponent needs digits (e.g. `1e-9`)".into()))?;
            let literal: String = chars[start..i].iter().collect();
            let value = literal
                .parse::<f64>()
                .map_err(|_| error(column, format!("`{literal}` is not a number")))?;
            tokens.push(Token {
                kind: TokenKind::Num(value),
                column,
            });
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push(Token {
                kind: TokenKind::Ident(chars[start..i].iter().collect()),
                column,
            });
            continue;
        }
        let (kind, len) =
            symbol(c, chars.get(i + 1).copied()).ok_or_else(|| error(column, format!("unexpected character `{c}`")))?;
        tokens.push(Token { kind, column });
        i += len;
    }
    tokens.push(Token {
        kind: TokenKind::End,
        column: chars.len() + 1,
    });
    Ok(tokens)
}

/// The end of the number literal that starts at `start`: digits, an optional fraction, an optional
/// exponent; `None` for an exponent without digits.
fn number_end(chars: &[char], start: usize) -> Option<usize> {
    let digits_from = |mut i: usize| {
        while i < chars.len() && chars[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = digits_from(start);
    if i < chars.len() && chars[i] == '.' {
        i = digits_from(i + 1);
    }
    if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
        let mut j = i + 1;
        if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
            j += 1;
        }
        if !(j < chars.len() && chars[j].is_ascii_digit()) {
            return None;
        }
        i = digits_from(j);
    }
    Some(i)
}

/// The punctuation or operator token that starts with `c` (followed by `next`) and its length in
/// characters; `**` is read as `^`.
fn symbol(c: char, next: Option<char>) -> Option<(TokenKind, usize)> {
    Some(match (c, next) {
        ('(', _) => (TokenKind::Open, 1),
        (')', _) => (TokenKind::Close, 1),
        (',', _) => (TokenKind::Comma, 1),
        ('<', Some('=')) => (TokenKind::Op("<="), 2),
        ('>', Some('=')) => (TokenKind::Op(">="), 2),
        ('=', Some('=')) => (TokenKind::Op("=="), 2),
        ('!', Some('=')) => (TokenKind::Op("!="), 2),
        ('&', Some('&')) => (TokenKind::Op("&&"), 2),
        ('|', Some('|')) => (TokenKind::Op("||"), 2),
        ('*', Some('*')) => (TokenKind::Op("^"), 2),
        ('<', _) => (TokenKind::Op("<"), 1),
        ('>', _) => (TokenKind::Op(">"), 1),
        ('!', _) => (TokenKind::Op("!"), 1),
        ('+', _) => (TokenKind::Op("+"), 1),
        ('-', _) => (TokenKind::Op("-"), 1),
        ('*', _) => (TokenKind::Op("*"), 1),
        ('/', _) => (TokenKind::Op("/"), 1),
        ('^', _) => (TokenKind::Op("^"), 1),
        _ => return None,
    })
}

pub(super) fn infix(op: &str) -> Option<Binary> {
    Binary::ALL.into_iter().find(|b| b.repr() == op && b.infix_precedence() <= 5)
}

/// What names mean while parsing one expression or function body.
pub(super) struct Scope<'a> {
    /// The scene variables allowed here.
    pub(super) variables: &'a [&'a str],
    /// The parameters of the user function being parsed.
    pub(super) params: &'a [String],
    /// User functions being expanded (cycle detection).
    pub(super) stack: Vec<&'a str>,
}

pub(super) struct Parser<'a> {
    context: &'a ExprContext,
    functions: &'a RefCell<FunctionTable>,
    text: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    depth: usize,
}

impl<'a> Parser<'a> {
    pub(super) fn new(
        context: &'a ExprContext,
        functions: &'a RefCell<FunctionTable>,
        text: &'a str,
    ) -> Result<Self, ExprError> {
        Ok(Self {
            context,
            functions,
            text,
            tokens: tokenize(text)?,
            pos: 0,
            depth: 0,
        })
    }

    pub(super) fn error(&self, column: usize, reason: impl Into<String>) -> ExprError {
        ExprError::Parse {
            expression: self.text.to_string(),
            column,
            reason: reason.into(),
        }
    }

    pub(super) fn peek(&self) -> &Token {
        &self.tokens[self.pos]
    }

    pub(super) fn advance(&mut self) -> Token {
        let t = self.tokens[self.pos].clone();
        if self.pos + 1 < self.tokens.len() {
            self.pos += 1;
        }
        t
    }

    pub(super) fn parse_all(&mut self, scope: &mut Scope<'a>) -> Result<Node, ExprError> {
        if self.peek().kind == TokenKind::End {
            return Err(self.error(1, "the expression is empty"));
        }
        let node = self.binary(1, scope)?;
        let t = self.peek();
        if t.kind != TokenKind::End {
            let found = describe(&t.kind);
            return Err(self.error(t.column, format!("unexpected {found} (missing an operator?)")));
        }
        Ok(node)
    }

    pub(super) fn binary(&mut self, min_precedence: u8, scope: &mut Scope<'a>) -> Result<Node, ExprError> {
        let mut lhs = self.unary(scope)?;
        loop {
            let op = match &self.peek().kind {
                TokenKind::Op(s) => infix(s),
                _ => None,
            };
            let Some(op) = op else { break };
            let precedence = op.infix_precedence();
            if precedence < min_precedence {
                break;
            }
            self.advance();
            let rhs = self.binary(precedence + 1, scope)?;
            lhs = Node::binary(op, lhs, rhs);
        }
        Ok(lhs)
    }

    pub(super) fn unary(&mut self, scope: &mut Scope<'a>) -> Result<Node, ExprError> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            let column = self.peek().column;
            return Err(self.error(column, format!("nested more than {MAX_NESTING} levels deep")));
        }
        let node = self.unary_inner(scope);
        self.depth -= 1;
        node
    }

    pub(super) fn unary_inner(&mut self, scope: &mut Scope<'a>) -> Result<Node, ExprError> {
        match self.peek().kind {
            TokenKind::Op("-") => {
                self.advance();
                Ok(Node::unary(Unary::Neg, self.unary(scope)?))
            }
            TokenKind::Op("+") => {
                self.advance();
                self.unary(scope)
            }
            TokenKind::Op("!") => {
                self.advance();
                Ok(Node::unary(Unary::Not, self.unary(scope)?))
            }
            _ => self.power(scope),
        }
    }

    pub(super) fn power(&mut self, scope: &mut Scope<'a>) -> Result<Node, ExprError> {
        let base = self.primary(scope)?;
        if self.peek().kind == TokenKind::Op("^") {
            self.advance();
            // Right-associative, and the exponent may carry a sign: `2^-1`, `2^3^2 = 2^9`.
            let exponent = self.unary(scope)?;
            return Ok(Node::binary(Binary::Pow, base, exponent));
        }
        Ok(base)
    }

    pub(super) fn primary(&mut self, scope: &mut Scope<'a>) -> Result<Node, ExprError> {
        let token = self.advance();
        match token.kind {
            TokenKind::Num(v) => Ok(Node::Num(v)),
            TokenKind::Open => {
                let inner = self.binary(1, scope)?;
                let close = self.advance();
                if close.kind != TokenKind::Close {
                    return Err(self.error(close.column, format!("expected `)`, found {}", describe(&close.kind))));
                }
                Ok(inner)
            }
            TokenKind::Ident(name) => {
                if self.peek().kind == TokenKind::Open {
                    self.advance();
                    let args = self.arguments(scope)?;
                    self.call(&name, token.column, args, scope)
                } else {
                    self.name(&name, token.column, scope)
                }
            }
            other => Err(self.error(
                token.column,
                format!("expected a number, a name or `(`, found {}", describe(&other)),
            )),
        }
    }

    pub(super) fn arguments(&mut self, scope: &mut Scope<'a>) -> Result<Vec<Node>, ExprError> {
        let mut args = Vec::new();
        if self.peek().kind == TokenKind::Close {
            self.advance();
            return Ok(args);
        }
        loop {
            args.push(self.binary(1, scope)?);
            let t = self.advance();
            match t.kind {
                TokenKind::Comma => continue,
                TokenKind::Close => return Ok(args),
                other => {
                    return Err(self.error(t.column, format!("expected `,` or `)`, found {}", describe(&other))));
                }
            }
        }
    }

    pub(super) fn name(&self, name: &str, column: usize, scope: &Scope<'a>) -> Result<Node, ExprError> {
        if let Some(i) = scope.params.iter().position(|p| p == name) {
            return Ok(Node::Param(i));
        }
        if let Some(i) = scope.variables.iter().position(|v| *v == name) {
            return Ok(Node::Var(i));
        }
        if let Some((_, value)) = CONSTANTS.iter().find(|(c, _)| *c == name) {
            return Ok(Node::Num(*value));
        }
        if is_builtin_function(name) || self.context.functions.contains_key(name) {
            return Err(self.error(column, format!("`{name}` is a function: call it as `{name}(…)`")));
        }
        let allowed: Vec<&str> = if scope.stack.is_empty() {
            scope.variables.to_vec()
        } else {
            scope.params.iter().map(String::as_str).collect()
        };
        Err(ExprError::UnknownVariable {
            expression: self.text.to_string(),
            name: name.to_string(),
            column,
            allowed: if allowed.is_empty() {
                "none".into()
            } else {
                allowed.join(", ")
            },
        })
    }

    pub(super) fn call(
        &self,
        name: &str,
        column: usize,
        args: Vec<Node>,
        scope: &mut Scope<'a>,
    ) -> Result<Node, ExprError> {
        let arity = |expected: &str, ok: bool| {
            if ok {
                Ok(())
            } else {
                Err(self.error(
                    column,
                    format!("`{name}` takes {expected} argument(s), got {}", args.len()),
                ))
            }
        };
        if let Some(op) = Unary::from_name(name) {
            arity("1", args.len() == 1)?;
            let [a]: [Node; 1] = args.try_into().expect("checked length");
            return Ok(Node::unary(op, a));
        }
        match name {
            "min" | "max" => {
                arity("2 or more", args.len() >= 2)?;
                let op = if name == "min" { Binary::Min } else { Binary::Max };
                let mut it = args.into_iter();
                let first = it.next().expect("checked length");
                return Ok(it.fold(first, |acc, a| Node::binary(op, acc, a)));
            }
            "atan2" => {
                arity("2", args.len() == 2)?;
                let [y, x]: [Node; 2] = args.try_into().expect("checked length");
                return Ok(Node::binary(Binary::Atan2, y, x));
            }
            "clamp" => {
                arity("3", args.len() == 3)?;
                let [x, lo, hi]: [Node; 3] = args.try_into().expect("checked length");
                return Ok(Node::binary(Binary::Min, Node::binary(Binary::Max, x, lo), hi));
            }
            "ramp" => {
                arity("3", args.len() == 3)?;
                let [t, t0, t1]: [Node; 3] = args.try_into().expect("checked length");
                let numerator = Node::binary(Binary::Sub, t, t0.clone());
                let denominator = Node::binary(Binary::Sub, t1, t0);
                return Ok(Node::unary(
                    Unary::Clamp01,
                    Node::binary(Binary::Div, numerator, denominator),
                ));
            }
            _ => {}
        }
        let Some((key, function)) = self.context.functions.get_key_value(name) else {
            return Err(ExprError::UnknownFunction {
                expression: self.text.to_string(),
                name: name.to_string(),
                column,
            });
        };
        arity(&function.params.len().to_string(), args.len() == function.params.len())?;
        let known = self.functions.borrow().names.iter().position(|n| n == key);
        let index = match known {
            Some(index) => index,
            None => {
                if scope.stack.contains(&key.as_str()) || scope.stack.len() >= MAX_CALL_DEPTH {
                    return Err(self.error(column, format!("function `{name}` calls itself")));
                }
                let body = self.context.parse_body(key, function, &scope.stack, self.functions)?;
                let mut table = self.functions.borrow_mut();
                let cost = body.cost(&table.costs);
                table.names.push(key.clone());
                table.bodies.push(body);
                table.costs.push(cost);
                table.names.len() - 1
            }
        };
        Ok(Node::call(index, args, &self.functions.borrow().bodies))
    }
}

pub(super) fn describe(kind: &TokenKind) -> String {
    match kind {
        TokenKind::Num(v) => format!("number `{v}`"),
        TokenKind::Ident(s) => format!("name `{s}`"),
        TokenKind::Op(s) => format!("`{s}`"),
        TokenKind::Open => "`(`".into(),
        TokenKind::Close => "`)`".into(),
        TokenKind::Comma => "`,`".into(),
        TokenKind::End => "the end of the expression".into(),
    }
}

pub(super) fn is_builtin_function(name: &str) -> bool {
    Unary::from_name(name).is_some() || matches!(name, "min" | "max" | "atan2" | "clamp" | "ramp")
}

pub(super) fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}
