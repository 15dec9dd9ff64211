//! OSQP on the backend-neutral conformance suite (`signorini_qp::conformance`).

use signorini_osqp::{OsqpBackend, OsqpSettings};
use signorini_qp::conformance::{assert_conforms, Conformance};

#[test]
fn osqp_conforms() {
    assert_conforms(
        &mut || Box::new(OsqpBackend::new(OsqpSettings::default())),
        &Conformance::default(),
    );
}
