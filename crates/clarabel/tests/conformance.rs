//! clarabel on the backend-neutral conformance suite (`signorini_qp::conformance`).

use signorini_clarabel::{ClarabelBackend, ClarabelSettings};
use signorini_qp::conformance::{assert_conforms, Conformance};

#[test]
fn clarabel_conforms() {
    assert_conforms(
        &mut || Box::new(ClarabelBackend::new(ClarabelSettings::default())),
        &Conformance::default(),
    );
}
