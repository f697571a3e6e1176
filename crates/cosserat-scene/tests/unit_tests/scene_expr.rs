//! Expressions: hand-computed values, precedence, user functions, and errors with columns.

use cosserat_scene::error::ExprError;
use cosserat_scene::expr::ExprContext;
use nalgebra::Vector3;
use std::f64::consts::PI;

fn eval(text: &str, vars: &[&str], values: &[f64]) -> f64 {
    ExprContext::new()
        .compile(text, vars)
        .unwrap_or_else(|e| panic!("{e}"))
        .eval(values)
}

#[test]
fn ramp_clamps_a_linear_rise() {
    let ctx = ExprContext::new();
    let f = ctx.time_function("ramp(t, 1, 5)").unwrap();
    for (t, expected) in [(-3.0, 0.0), (1.0, 0.0), (2.0, 0.25), (3.0, 0.5), (5.0, 1.0), (9.0, 1.0)] {
        assert_eq!(f.eval(t), expected, "ramp at t = {t}");
    }
    // The plate's load scale and the strip's twist angle.
    assert_eq!(eval("50*ramp(t, 0, 1)", &["t"], &[0.3]), 15.0);
    assert_eq!(eval("2*pi*t", &["t"], &[0.25]), PI / 2.0);
}

#[test]
fn sgn_is_minus_one_at_zero() {
    for (x, expected) in [(-2.0, -1.0), (-0.0, -1.0), (0.0, -1.0), (1e-300, 1.0), (3.0, 1.0)] {
        assert_eq!(eval("sgn(x)", &["x"], &[x]), expected, "sgn({x})");
        assert_eq!(eval("sign(x)", &["x"], &[x]), expected, "sign({x})");
    }
}

#[test]
fn lotus_profile_matches_the_polynomial() {
    let mut ctx = ExprContext::new();
    ctx.define(
        "p",
        &["u".into()],
        "-0.2314286 + 10.89881*u - 14.28571*u^2 + 4.427083*u^3",
    )
    .unwrap();
    let f = ctx.compile("p(u)", &["u"]).unwrap();
    // Hand-computed: p(0) = −0.2314286; p(1) = −0.2314286 + 10.89881 − 14.28571 + 4.427083 = 0.8087544;
    // p(0.5) = −0.2314286 + 5.449405 − 3.5714275 + 0.553385375 = 2.199934275.
    assert_eq!(f.eval(&[0.0]), -0.2314286);
    assert!((f.eval(&[1.0]) - 0.8087544).abs() < 1e-12);
    assert!((f.eval(&[0.5]) - 2.199934275).abs() < 1e-12);
    // Nested calls with a time-dependent argument, as in the lotus scene.
    ctx.define("sigma", &["t".into()], "min(t/6 + 1, 1.8)").unwrap();
    let g = ctx.field_function("0.35*p(sigma(t)*abs(x)/0.5)").unwrap();
    assert!(g.is_time_dependent());
    // t = 3: σ = 1.5, u = 1.5·0.2/0.5 = 0.6;
    // p(0.6) = −0.2314286 + 6.539286 − 5.1428556 + 0.956249928 = 2.121251728.
    let p06 = 2.121251728;
    assert!((g.eval(&Vector3::new(-0.2, 0.0, 0.0), 3.0) - 0.35 * p06).abs() < 1e-12);
}

#[test]
fn precedence_follows_mathematics() {
    assert_eq!(eval("-x^2", &["x"], &[3.0]), -9.0);
    assert_eq!(eval("2^3^2", &[], &[]), 512.0);
    assert_eq!(eval("x^-1", &["x"], &[4.0]), 0.25);
    assert_eq!(eval("8 - 3 - 2", &[], &[]), 3.0);
    assert_eq!(eval("x / 2 / 2", &["x"], &[8.0]), 2.0);
    assert_eq!(eval("1 + 2 * 3 < 8 && 2 > 1", &[], &[]), 1.0);
    assert_eq!(eval("x <= -0.05 + 1e-9", &["x"], &[-0.05]), 1.0);
    assert_eq!(eval("x <= -0.05 + 1e-9", &["x"], &[-0.0499]), 0.0);
    assert_eq!(eval("!(x > 0) || y == 2", &["x", "y"], &[1.0, 2.0]), 1.0);
    assert_eq!(eval("2.5E+3 + .5 + 1e-1", &[], &[]), 2500.6);
}

#[test]
fn functions_of_several_arguments() {
    assert_eq!(eval("clamp(x, -1, 1)", &["x"], &[4.0]), 1.0);
    assert_eq!(eval("clamp(x, -1, 1)", &["x"], &[-4.0]), -1.0);
    assert_eq!(eval("min(x, 3, 2, 5)", &["x"], &[4.0]), 2.0);
    assert_eq!(eval("max(x, y)", &["x", "y"], &[-1.0, -2.0]), -1.0);
    assert_eq!(eval("atan2(y, x)", &["x", "y"], &[0.0, 1.0]), PI / 2.0);
    // The scroll's capped curvature: min(M·u³, 100).
    assert_eq!(eval("min(2000*pi*x^3, 100)", &["x"], &[0.5]), 100.0);
    assert!((eval("min(2000*pi*x^3, 100)", &["x"], &[0.1]) - 2.0 * PI).abs() < 1e-12);
}

#[test]
fn variables_are_mapped_whatever_the_order() {
    let e = ExprContext::new().compile("100*t + 10*y + z", &["x", "y", "z", "t"]).unwrap();
    assert_eq!(e.eval(&[9.0, 1.0, 2.0, 3.0]), 312.0);
    assert!(!e.uses(0) && e.uses(1) && e.uses(3));
    assert!(ExprContext::new().compile("3 * pi", &["t"]).unwrap().is_constant());
}

#[test]
fn unknown_variable_names_the_column_and_the_allowed_ones() {
    let err = ExprContext::new().compile("2*t + q", &["t"]).unwrap_err();
    assert!(
        matches!(err, ExprError::UnknownVariable { ref name, column: 7, .. } if name == "q"),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        "`2*t + q`: column 7: unknown variable `q` (allowed here: t)"
    );
}

#[test]
fn syntax_errors_name_the_column() {
    let cases = [
        ("2 * (t + 1", 11, "expected `)`"),
        ("2 t", 3, "unexpected name `t`"),
        ("ramp(t, 0)", 1, "`ramp` takes 3 argument(s), got 2"),
        ("3 $ 4", 3, "unexpected character `$`"),
        ("1e+", 1, "exponent needs digits"),
        ("sin", 1, "`sin` is a function"),
        ("", 1, "empty"),
    ];
    for (text, column, needle) in cases {
        let err = ExprContext::new().compile(text, &["t"]).unwrap_err();
        match &err {
            ExprError::Parse { column: c, reason, .. } => {
                assert_eq!(*c, column, "{text}: {err}");
                assert!(reason.contains(needle), "{text}: {err}");
            }
            other => panic!("{text}: expected a parse error, got {other:?}"),
        }
    }
    let err = ExprContext::new().compile("foo(t)", &["t"]).unwrap_err();
    assert!(matches!(err, ExprError::UnknownFunction { ref name, column: 1, .. } if name == "foo"));
}

#[test]
fn constant_division_by_zero_is_rejected() {
    let err = ExprContext::new().compile("t + 1/0", &["t"]).unwrap_err();
    assert!(
        matches!(err, ExprError::NonFinite { value, .. } if value == f64::INFINITY),
        "{err:?}"
    );
}

#[test]
fn user_function_definitions_are_checked() {
    let mut ctx = ExprContext::new();
    assert!(matches!(ctx.define("sin", &[], "1"), Err(ExprError::Definition { .. })));
    assert!(matches!(ctx.define("x", &[], "1"), Err(ExprError::Definition { .. })));
    assert!(matches!(
        ctx.define("f", &["a".into(), "a".into()], "a"),
        Err(ExprError::Definition { .. })
    ));
    ctx.define("f", &["a".into()], "g(a) + 1").unwrap();
    ctx.define("g", &["a".into()], "f(a)").unwrap();
    let err = ctx.check_functions().unwrap_err();
    assert!(err.to_string().contains("calls itself"), "{err}");
    let mut ctx = ExprContext::new();
    ctx.define("h", &["a".into()], "a + t").unwrap();
    let err = ctx.check_functions().unwrap_err();
    assert!(
        err.to_string().contains("unknown variable `t` (allowed here: a)"),
        "{err}"
    );
}

#[test]
fn predicates_must_be_boolean() {
    let ctx = ExprContext::new();
    let p = ctx.predicate("abs(y) < 0.01 && z >= 0").unwrap();
    assert!(p.test(&Vector3::new(5.0, 0.005, 0.0)).unwrap());
    assert!(!p.test(&Vector3::new(5.0, 0.02, 0.0)).unwrap());
    let p = ctx.predicate("x + 0.05").unwrap();
    let err = p.test(&Vector3::new(0.1, 0.0, 0.0)).unwrap_err();
    assert!(matches!(err, ExprError::NotBoolean { .. }));
}

#[test]
fn predicates_refuse_infinite_or_nan_parts() {
    // The comparisons give 0 or 1 everywhere, but their operands are not numbers at some nodes: the
    // first would silently select the nodes at positive x, the second none at negative x.
    let mut ctx = ExprContext::new();
    ctx.define("inv", &["u".into()], "1 / u").unwrap();
    for (text, at) in [
        ("x / 0 > 1", Vector3::new(0.5, 0.0, 0.0)),
        ("sqrt(x) < 1 || y > 0", Vector3::new(-0.5, 0.0, 0.0)),
        ("inv(x) > 0", Vector3::new(0.0, 1.0, 0.0)),
    ] {
        let p = ctx.predicate(text).unwrap();
        let err = p.test(&at).unwrap_err();
        assert!(matches!(err, ExprError::NonFiniteOperand { .. }), "{text}: {err:?}");
        assert!(err.to_string().contains("division by zero"), "{err}");
    }
    // The same with constants: folding the comparison must not hide the NaN.
    for text in ["sqrt(-1) < 1", "!(0/0)", "min(ln(0), 1) > 0 || x > 0"] {
        let err = ctx.predicate(text).unwrap_err();
        assert!(matches!(err, ExprError::NonFinite { .. }), "{text}: {err:?}");
    }
    // Finite operands everywhere: unchanged.
    let p = ctx.predicate("x / 2 > 0.1 && sqrt(abs(y)) < 1").unwrap();
    assert!(p.test(&Vector3::new(0.5, -0.25, 0.0)).unwrap());
}

#[test]
fn pathological_nesting_is_an_error_not_a_stack_overflow() {
    let deep = format!("{}t{}", "(".repeat(10_000), ")".repeat(10_000));
    let err = ExprContext::new().compile(&deep, &["t"]).unwrap_err();
    assert!(
        matches!(err, ExprError::Parse { ref reason, .. } if reason.contains("nested more than")),
        "{err:?}"
    );
    let minus = format!("{}t", "-".repeat(10_000));
    assert!(ExprContext::new().compile(&minus, &["t"]).is_err());
    // Fifty levels are fine.
    let fifty = format!("{}t{}", "(".repeat(50), ")".repeat(50));
    assert_eq!(ExprContext::new().compile(&fifty, &["t"]).unwrap().eval(&[2.0]), 2.0);
}

#[test]
fn helpers_that_call_each_other_are_called_not_copied() {
    // f0(u) = u + 1 and f_k(u) = f_{k-1}(u) + f_{k-1}(2u): copied into one another, the formula of f_k
    // would double with every k; called, each body is parsed once. f_k(u) = 2^k u + Σ… is checked
    // against the recursion evaluated here.
    fn reference(k: usize, u: f64) -> f64 {
        if k == 0 {
            u + 1.0
        } else {
            reference(k - 1, u) + reference(k - 1, 2.0 * u)
        }
    }
    let mut ctx = ExprContext::new();
    ctx.define("f0", &["u".into()], "u + 1").unwrap();
    for k in 1..=12 {
        let body = format!("f{}(u) + f{}(2*u)", k - 1, k - 1);
        ctx.define(&format!("f{k}"), &["u".into()], &body).unwrap();
    }
    let f6 = ctx.compile("f6(t)", &["t"]).unwrap();
    for t in [0.0, 0.5, -3.0] {
        assert_eq!(f6.eval(&[t]), reference(6, t));
    }
    // Twelve levels take 2^12 calls per evaluation: allowed. A chain whose evaluation would pass the
    // limit of operations is refused when it is compiled, naming the cost.
    assert_eq!(ctx.compile("f12(t)", &["t"]).unwrap().eval(&[1.0]), reference(12, 1.0));
    for k in 13..=20 {
        let body = format!("f{}(u) + f{}(2*u)", k - 1, k - 1);
        ctx.define(&format!("f{k}"), &["u".into()], &body).unwrap();
    }
    let err = ctx.compile("f20(t)", &["t"]).unwrap_err().to_string();
    assert!(
        err.contains("one evaluation would take") && err.contains("more than the limit of 100000"),
        "{err}"
    );
    assert!(ctx.check_functions().is_err(), "the costly definition is reported too");
}
