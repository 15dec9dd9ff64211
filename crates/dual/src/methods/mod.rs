//! The dual methods, one file each: projected Gauss–Seidel ([`pgs`]), Uzawa / accelerated
//! projected gradient ([`uzawa`]) and the primal–dual active set ([`ssn`]).

mod newton;
pub mod pgs;
pub mod ssn;
pub mod uzawa;
