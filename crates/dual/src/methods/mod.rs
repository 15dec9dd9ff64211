//! The dual methods, one file each: projected Gauss–Seidel ([`pgs`]), Uzawa / accelerated
//! projected gradient ([`uzawa`]) and the primal–dual active set ([`ssn`]); the projected two
//! share each multiplier's interval ([`intervals`]).

mod intervals;
mod newton;
pub mod pgs;
pub mod ssn;
pub mod uzawa;
