!> *MAT_MOONEY-RIVLIN_RUBBER: nearly incompressible Mooney-Rivlin law (neo-Hookean for B = 0)
!> with the isochoric/volumetric split
!>
!>   W = A (I1_bar - 3) + B (I2_bar - 3) + U(J),   U(J) = kappa/2 (1/2 (J^2 - 1) - ln J),
!>   b_bar = J^(-2/3) F F^T, I1_bar = tr b_bar, I2_bar = (I1_bar^2 - tr(b_bar^2))/2,
!>   tau = kappa/2 (J^2 - 1) 1 + 2 dev(Y),   Y = (A + B I1_bar) b_bar - B b_bar^2,
!>
!> small-strain shear modulus mu = 2 (A + B), bulk modulus from PR:
!> kappa = 2 mu (1 + PR)/(3 (1 - 2 PR)) (so the reader's E = 2 mu (1 + PR) is the matching
!> Young's modulus). U is the volumetric function of the J2 law (mefem_mat_j2_plasticity):
!> it is convex, U -> infinity as J -> 0 (an element cannot be squeezed to zero volume, unlike
!> kappa/2 (J - 1)^2), and gives p = kappa (J - 1) to first order.
!> This differs from LS-DYNA's *MAT_027 energy (A (I - 3) + B (II - 3) + C (III^-2 - 1)
!> + D (III - 1)^2, not split into isochoric and volumetric parts) at finite volume change;
!> the small-strain constants and the incompressible limit are the same.
!>
!> Tangent (L_v tau = c : d), with Z = (A + 2 B I1_bar) b_bar - 2 B b_bar^2 and
!> (b (.) b)_ijkl = (b_ik b_jl + b_il b_jk)/2:
!>   c = kappa J^2 1(x)1 - kappa (J^2 - 1) I
!>     + 4 B b_bar(x)b_bar - 4 B b_bar(.)b_bar - 4/3 (Z(x)1 + 1(x)Z) + 4/9 tr(Z) 1(x)1
!>     + 4/3 tr(Y) I
!> (from L_v b_bar = -2/3 tr(d) b_bar; symmetric, as for any hyperelastic law).
!> Wave speed: c = sqrt((kappa + 4/3 mu_eff)/rho0) with the volumetric longitudinal modulus
!> kappa (exact for this U) and the estimate mu_eff = 2 (A I1_bar + B I2_bar)/3 (= mu at small
!> strain, never smaller since I1_bar, I2_bar >= 3).
module mefem_mat_mooney_rivlin
  use mefem_kinds, only: wp
  use mefem_model, only: material_t
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa, rtoa
  use mefem_tensor_algebra, only: IDENTITY, determinant, trace, deviator, add_outer_product, &
                                  add_symmetric_identity, add_symmetric_product
  use mefem_material_state, only: NHIST
  implicit none
  private

  public :: mat_mooney_rivlin_update

contains

  !> Stress, history, wave speed and (optionally) tangent of the Mooney-Rivlin law at F.
  pure subroutine mat_mooney_rivlin_update(mat, f_new, hist_old, hist_new, tau, sound_speed, &
                                           status, c_tau)
    type(material_t), intent(in) :: mat                !< *MAT_027 parameters (A, B, PR, RO)
    real(wp), intent(in) :: f_new(3,3)                  !< deformation gradient F_{n+1}
    real(wp), intent(in) :: hist_old(NHIST)             !< history at t_n
    real(wp), intent(out) :: hist_new(NHIST)            !< history at t_{n+1}
    real(wp), intent(out) :: tau(3,3)                   !< Kirchhoff stress
    real(wp), intent(out) :: sound_speed                !< dilatational wave speed
    type(status_t), intent(out) :: status               !< fails for det F <= 0
    real(wp), intent(out), optional :: c_tau(3,3,3,3)   !< spatial tangent of tau
    real(wp) :: a, b, mu, kappa, j, jp, i1, i2, mu_effective
    real(wp) :: b_bar(3,3), b_bar2(3,3), y(3,3), z(3,3)
    hist_new = hist_old
    tau = 0.0_wp
    sound_speed = 0.0_wp
    if (present(c_tau)) c_tau = 0.0_wp
    j = determinant(f_new)
    if (.not. (j > 0.0_wp)) then
      status%ok = .false.
      status%message = 'material '//itoa(mat%id)//': det F = '//rtoa(j)// &
                       ' <= 0 (inverted or degenerate element)'
      return
    end if
    a = mat%mr_a
    b = mat%mr_b
    mu = 2.0_wp*(a + b)
    kappa = 2.0_wp*mu*(1.0_wp + mat%poisson)/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
    b_bar = j**(-2.0_wp/3.0_wp)*matmul(f_new, transpose(f_new))
    b_bar2 = matmul(b_bar, b_bar)
    i1 = trace(b_bar)
    i2 = 0.5_wp*(i1*i1 - trace(b_bar2))
    y = (a + b*i1)*b_bar - b*b_bar2
    jp = 0.5_wp*kappa*(j*j - 1.0_wp)
    tau = 2.0_wp*deviator(y) + jp*IDENTITY
    mu_effective = 2.0_wp*(a*i1 + b*i2)/3.0_wp
    sound_speed = sqrt((kappa + 4.0_wp/3.0_wp*mu_effective)/mat%density)
    if (.not. present(c_tau)) return
    z = (a + 2.0_wp*b*i1)*b_bar - 2.0_wp*b*b_bar2
    call add_outer_product(c_tau, kappa*j*j, IDENTITY, IDENTITY)
    call add_symmetric_identity(c_tau, -2.0_wp*jp)
    call add_outer_product(c_tau, 4.0_wp*b, b_bar, b_bar)
    call add_symmetric_product(c_tau, -4.0_wp*b, b_bar, b_bar)
    call add_outer_product(c_tau, -4.0_wp/3.0_wp, z, IDENTITY)
    call add_outer_product(c_tau, -4.0_wp/3.0_wp, IDENTITY, z)
    call add_outer_product(c_tau, 4.0_wp/9.0_wp*trace(z), IDENTITY, IDENTITY)
    call add_symmetric_identity(c_tau, 4.0_wp/3.0_wp*trace(y))
  end subroutine mat_mooney_rivlin_update

end module mefem_mat_mooney_rivlin
