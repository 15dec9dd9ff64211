//! pdas, from each of its starting sets, on the backend-neutral conformance suite
//! (`signorini_qp::conformance`).

use signorini_pdas::{PdasBackend, PdasSettings, StartSet};
use signorini_qp::conformance::{assert_conforms, Conformance};

#[test]
fn pdas_conforms_from_every_start() {
    for start in StartSet::EVERY {
        assert_conforms(
            &mut || {
                Box::new(PdasBackend::new(PdasSettings {
                    start,
                    ..PdasSettings::default()
                }))
            },
            &Conformance::default(),
        );
    }
}
