//! Screening a pair's rows against the supports: inert rows removed, prescribed penetration
//! refused, the pair's warnings gathered.

use super::error::ModelError;
use super::rows::row_entries;
use super::warnings::{ModelWarning, NoRowReason};
use crate::contact::PairRows;
use crate::effects::ContactEffect;
use crate::fem::Dofs;

/// Removes a pair's inert rows (every DOF with a non-zero coefficient prescribed) and returns
/// the pair's warnings; refuses an inert row whose reduced gap g − B_D u_D is below −tolerance.
pub(super) fn screen_pair(
    contact: &ContactEffect<'_>,
    dofs: &Dofs,
    fixed: &[Option<f64>],
    pair: &mut PairRows,
) -> Result<Vec<ModelWarning>, ModelError> {
    let tol = contact.tol;
    let interface = &contact.interfaces[pair.pair];
    let name = |b: usize| interface.side(b).name.to_string();
    let number = pair.pair + 1;
    let mut warnings = Vec::new();
    let mut inert = 0;
    let mut first = None;
    let mut kept = Vec::with_capacity(pair.rows.len());
    for r in std::mem::take(&mut pair.rows) {
        let entries = row_entries(dofs, pair, &r);
        let mut lifted = 0.0;
        let mut all_fixed = true;
        for &(d, v) in entries.iter().filter(|(_, v)| *v != 0.0) {
            match fixed[d] {
                Some(u) => lifted += v * u,
                None => all_fixed = false,
            }
        }
        if !all_fixed {
            kept.push(r);
            continue;
        }
        let reduced = r.gap - lifted;
        if reduced < -tol {
            return Err(ModelError::PrescribedPenetration {
                pair: number,
                slave: name(pair.slave),
                master: name(pair.master),
                point: r.position,
                gap: reduced,
            });
        }
        inert += 1;
        first.get_or_insert(r.position);
    }
    pair.rows = kept;
    let (slave, master) = (name(pair.slave), name(pair.master));
    if let Some(o) = &pair.overlap {
        warnings.push(ModelWarning::InitialOverlap {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            nodes: o.slave_nodes,
            master_nodes: o.master_nodes,
            deepest_body: name(o.deepest_body),
            deepest: o.deepest,
            depth: o.depth,
        });
    }
    if pair.unmatched > 0 && pair.unmatched < pair.candidates {
        warnings.push(ModelWarning::UnmatchedNodes {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            nodes: pair.unmatched,
            candidates: pair.candidates,
        });
    }
    if pair.tributary_fallbacks > 0 {
        warnings.push(ModelWarning::TributaryFallback {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            rows: pair.tributary_fallbacks,
            unit_length: pair.unit_tributaries,
        });
    }
    if let Some(first) = first {
        warnings.push(ModelWarning::InertRows {
            pair: number,
            slave: slave.clone(),
            master: master.clone(),
            rows: inert,
            first,
        });
    }
    if pair.rows.is_empty() {
        let reason = if inert > 0 {
            NoRowReason::AllInert
        } else if pair.candidates == 0 {
            NoRowReason::NoCandidates
        } else {
            NoRowReason::NoFacingSegment
        };
        let [k, l] = interface.sides.map(|s| s.body);
        warnings.push(ModelWarning::NoContactRow {
            pair: number,
            bodies: [name(k), name(l)],
            reason,
        });
    }
    Ok(warnings)
}
