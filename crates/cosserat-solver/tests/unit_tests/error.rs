//! Error messages name what failed, and every Newton error exposes its residual history.

use cosserat_solver::time_step::FailedAttempt;
use cosserat_solver::{
    Factorisation, LevelFailure, LinearSolveError, NewtonError, NonFiniteQuantity, PathError, ProblemError,
    StaticError, StepError,
};

#[test]
fn messages_name_the_failing_entry() {
    let e = LinearSolveError::NonFiniteValue {
        index: 4,
        row: 1,
        col: 2,
        value: f64::NAN,
    };
    assert_eq!(e.to_string(), "matrix value #4 at (1, 2) is not finite: NaN");
    let e = LinearSolveError::Singular {
        factorisation: Factorisation::Lblt,
        col: Some(7),
    };
    assert_eq!(
        e.to_string(),
        "the matrix is singular (LBLᵀ factorisation, zero pivot at column 7)"
    );
    let e = LinearSolveError::Singular {
        factorisation: Factorisation::Lu,
        col: None,
    };
    assert_eq!(e.to_string(), "the matrix is singular (LU factorisation)");
    let e = ProblemError::NonFiniteEnergy {
        index: 12,
        part: "term `gravity` at node 12".into(),
    };
    assert_eq!(e.to_string(), "non-finite energy in term `gravity` at node 12");
}

#[test]
fn newton_errors_expose_residuals_and_sources() {
    let e = NewtonError::MaxIterations {
        iterations: 2,
        residuals: vec![3.0, 2.0, 1.0],
    };
    assert_eq!(e.residuals(), &[3.0, 2.0, 1.0]);
    assert_eq!(
        e.to_string(),
        "no convergence in 2 Newton iterations (last residual 1e0)"
    );
    let e = NewtonError::LinearSolve {
        iteration: 3,
        source: LinearSolveError::NotPositiveDefinite { col: 5 },
        residuals: vec![1.0],
    };
    assert_eq!(e.residuals(), &[1.0]);
    let source = std::error::Error::source(&e).expect("linear error is the source");
    assert_eq!(
        source.to_string(),
        "the matrix is not positive definite (non-positive pivot at column 5)"
    );
    let e = NewtonError::NonFinite {
        iteration: 0,
        quantity: NonFiniteQuantity::Gradient,
        index: Some(3),
        residuals: vec![],
    };
    assert!(e.to_string().contains("Gradient") && e.to_string().contains('3'));
    assert!(NewtonError::PatternChanged.residuals().is_empty());
}

/// Times, step sizes and load factors far from 1 are written with an exponent, not as long decimals.
#[test]
fn tiny_times_and_step_sizes_are_written_with_an_exponent() {
    let e = StepError::NotConverged {
        t: 5e-8,
        attempts: vec![FailedAttempt {
            dt: 1e-8,
            error: NewtonError::MaxIterations {
                iterations: 2,
                residuals: vec![3.0, 2.0, 1.0],
            },
        }],
    };
    assert_eq!(
        e.to_string(),
        "time step from t = 5e-8 failed after 1 attempt(s); last: dt = 1e-8: no convergence in 2 Newton \
         iterations (last residual 1e0)"
    );
    let e = PathError::TooManySteps {
        end: 1.0,
        steps: 1000,
        load_factor: 1e-297,
    };
    assert_eq!(
        e.to_string(),
        "the path did not reach load factor 1 within 1000 steps (last load factor 1e-297)"
    );
    let e = StaticError {
        from: 0.0,
        to: 3e-9,
        error: LevelFailure::Newton(NewtonError::MaxIterations {
            iterations: 2,
            residuals: vec![1.0],
        }),
        iterations: 2,
        bisections: 0,
        sub_levels: 0,
    };
    assert!(
        e.to_string()
            .starts_with("quasi-static solve failed between load factors 0 and 3e-9:"),
        "{e}"
    );
}
