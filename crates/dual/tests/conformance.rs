//! The three dual methods on the backend-neutral conformance suite
//! (`signorini_qp::conformance`).

use signorini_dual::{DualBackend, DualMethod, DualSettings};
use signorini_qp::conformance::{assert_conforms, Conformance};

#[test]
fn every_dual_method_conforms() {
    for method in [
        DualMethod::ProjectedGaussSeidel,
        DualMethod::Uzawa,
        DualMethod::ActiveSet,
    ] {
        assert_conforms(
            &mut || {
                Box::new(DualBackend::new(DualSettings {
                    method,
                    ..DualSettings::default()
                }))
            },
            &Conformance::default(),
        );
    }
}
