//! An isotropic linear-elastic material under a plane idealisation: its elasticity matrix D
//! (σ = D ε with ε = (εₓₓ, εᵧᵧ, γₓᵧ)), its surface compliance, the out-of-plane stress and the
//! von Mises stress.

use nalgebra::SMatrix;

use crate::scene::{Body, Plane};

/// The 3×3 elasticity matrix D.
pub type Elasticity = SMatrix<f64, 3, 3>;

/// An isotropic linear-elastic material under a plane idealisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Plane strain or plane stress.
    pub plane: Plane,
}

impl Material {
    /// The material of a scene body under the scene's plane idealisation.
    pub fn of_body(body: &Body, plane: Plane) -> Self {
        Self {
            young: body.young,
            poisson: body.poisson,
            plane,
        }
    }

    /// The in-plane modulus E′ that relates a surface pressure to the surface's give in the 2-D
    /// half-space (Johnson, *Contact Mechanics*, §2.8): E/(1−ν²) in plane strain, where the
    /// out-of-plane strain is held at zero, and E in plane stress, where the out-of-plane
    /// stress is zero.
    pub fn plane_modulus(&self) -> f64 {
        match self.plane {
            Plane::Strain => self.young / (1.0 - self.poisson * self.poisson),
            Plane::Stress => self.young,
        }
    }

    /// The surface compliance 1/E′ ([`Self::plane_modulus`]): how far the body's surface gives
    /// under a pressure, relative to another body's.
    pub fn surface_compliance(&self) -> f64 {
        1.0 / self.plane_modulus()
    }

    /// Lamé's first parameter λ = Eν / ((1+ν)(1−2ν)).
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Shear modulus μ = E / (2(1+ν)).
    pub fn mu(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// D such that σ = D ε (plane strain: [[λ+2μ, λ, 0], [λ, λ+2μ, 0], [0, 0, μ]];
    /// plane stress: E/(1−ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]]).
    pub fn elasticity(&self) -> Elasticity {
        match self.plane {
            Plane::Strain => {
                let (l, m) = (self.lambda(), self.mu());
                Elasticity::new(l + 2.0 * m, l, 0.0, l, l + 2.0 * m, 0.0, 0.0, 0.0, m)
            }
            Plane::Stress => {
                let (e, nu) = (self.young, self.poisson);
                let c = e / (1.0 - nu * nu);
                Elasticity::new(
                    c,
                    c * nu,
                    0.0,
                    c * nu,
                    c,
                    0.0,
                    0.0,
                    0.0,
                    c * (1.0 - nu) / 2.0,
                )
            }
        }
    }

    /// Out-of-plane stress σ_zz for in-plane stresses: ν(σₓₓ + σᵧᵧ) in plane strain, 0 in plane
    /// stress.
    pub fn sigma_zz(&self, sxx: f64, syy: f64) -> f64 {
        match self.plane {
            Plane::Strain => self.poisson * (sxx + syy),
            Plane::Stress => 0.0,
        }
    }
}

/// Von Mises equivalent stress of (σₓₓ, σᵧᵧ, σₓᵧ, σ_zz).
pub fn von_mises(s: [f64; 4]) -> f64 {
    let [sxx, syy, sxy, szz] = s;
    (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2)) + 3.0 * sxy * sxy)
        .sqrt()
}
