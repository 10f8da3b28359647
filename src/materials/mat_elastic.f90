!> *MAT_ELASTIC at finite strain: the compressible neo-Hookean law
!>
!>   W = mu/2 (tr b - 3) - mu ln J + lambda/2 (ln J)^2,
!>   tau = mu (b - 1) + lambda ln(J) 1            (Kirchhoff stress, b = F F^T, J = det F)
!>   c   = lambda 1 (x) 1 + 2 (mu - lambda ln J) I (tangent of the Lie derivative of tau)
!>
!> with the Lame constants of E and PR: lambda = E nu/((1+nu)(1-2nu)), mu = E/(2(1+nu)).
!> Why this law: it is hyperelastic (no energy drift, exactly objective, path independent),
!> its small-strain limit is Hooke's law with the same E and nu (linearising at F = I gives
!> tau = lambda tr(eps) 1 + 2 mu eps), and W -> infinity as J -> 0, so it stays stable in
!> strong compression, where the St Venant-Kirchhoff law (Hooke's law in Green-Lagrange
!> strain) softens and loses stability. In simple shear the shear stress is mu gamma exactly.
!>
!> Wave speed for the explicit time step: c = sqrt(M/rho0) with M the longitudinal modulus of
!> c above, M = lambda + 2 mu - 2 lambda ln J, taken no smaller than its small-strain value
!> lambda + 2 mu = K + 4/3 G (c of tau per reference volume over rho0 is the current wave speed
!> up to the small stress term; the floor keeps the estimate on the safe side in tension).
module mefem_mat_elastic
  use mefem_kinds, only: wp
  use mefem_model, only: material_t
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa, rtoa
  use mefem_tensor_algebra, only: IDENTITY, determinant, add_outer_product, &
                                  add_symmetric_identity, natural_log
  use mefem_material_state, only: NHIST, BLOCK_POINTS
  implicit none
  private

  public :: mat_elastic_update, mat_elastic_update_block, lame_constants

contains

  !> Lame constants lambda and mu of Young's modulus and Poisson's ratio.
  pure subroutine lame_constants(young, poisson, lambda, mu)
    real(wp), intent(in) :: young, poisson   !< E and nu (-1 < nu < 0.5)
    real(wp), intent(out) :: lambda, mu      !< Lame's first constant and the shear modulus
    mu = young/(2.0_wp*(1.0_wp + poisson))
    lambda = young*poisson/((1.0_wp + poisson)*(1.0_wp - 2.0_wp*poisson))
  end subroutine lame_constants

  !> Stress, history, wave speed and (optionally) tangent of the neo-Hookean law at F.
  pure subroutine mat_elastic_update(mat, f_new, hist_old, hist_new, tau, sound_speed, status, &
                                     c_tau)
    type(material_t), intent(in) :: mat                !< *MAT_ELASTIC parameters
    real(wp), intent(in) :: f_new(3,3)                  !< deformation gradient F_{n+1}
    real(wp), intent(in) :: hist_old(NHIST)             !< history at t_n
    real(wp), intent(out) :: hist_new(NHIST)            !< history at t_{n+1}
    real(wp), intent(out) :: tau(3,3)                   !< Kirchhoff stress
    real(wp), intent(out) :: sound_speed                !< dilatational wave speed
    type(status_t), intent(out) :: status               !< fails for det F <= 0
    real(wp), intent(out), optional :: c_tau(3,3,3,3)   !< spatial tangent of tau
    real(wp) :: lambda, mu, j, log_j, b(3,3), modulus, pressure
    integer :: a, k
    hist_new = hist_old
    sound_speed = 0.0_wp
    if (present(c_tau)) c_tau = 0.0_wp
    j = determinant(f_new)
    if (.not. (j > 0.0_wp)) then
      tau = 0.0_wp
      status%ok = .false.
      status%message = 'material '//itoa(mat%id)//': det F = '//rtoa(j)// &
                       ' <= 0 (inverted or degenerate element)'
      return
    end if
    call lame_constants(mat%young, mat%poisson, lambda, mu)
    log_j = log(j)
    ! b = F F^T (upper triangle, mirrored: exactly symmetric)
    do k = 1, 3
      do a = 1, k
        b(a, k) = f_new(a, 1)*f_new(k, 1) + f_new(a, 2)*f_new(k, 2) + f_new(a, 3)*f_new(k, 3)
        b(k, a) = b(a, k)
      end do
    end do
    tau = mu*b
    pressure = lambda*log_j
    do k = 1, 3
      tau(k, k) = mu*(b(k, k) - 1.0_wp) + pressure
    end do
    modulus = lambda + 2.0_wp*mu + 2.0_wp*lambda*max(0.0_wp, -log_j)
    sound_speed = sqrt(modulus/mat%density)
    if (present(c_tau)) then
      call add_outer_product(c_tau, lambda, IDENTITY, IDENTITY)
      call add_symmetric_identity(c_tau, 2.0_wp*(mu - lambda*log_j))
    end if
  end subroutine mat_elastic_update

  !> The explicit update of a block of n points (no tangent, no wave speed; the history does
  !> not change): mat_elastic_update's arithmetic per point, structure of arrays (entry i of
  !> every array is point i) so that the compiler vectorises across points. ln J is taken
  !> point by point through natural_log, a call the compiler cannot vectorise: libmvec's log
  !> differs from libm's in the last bits, and a point's bits must not depend on its place in
  !> the block (the same bits on any number of ranks). A point with J <= 0 gets ok(i) =
  !> .false. and no stress (the caller calls mat_elastic_update on it for the message).
  !> f(i, 1:9): F_{n+1} column by column; j(i) = det F_{n+1}; tau(i, 1:6): Kirchhoff stress
  !> XX YY ZZ XY YZ ZX.
  subroutine mat_elastic_update_block(mat, n, f, j, tau, ok)
    type(material_t), intent(in) :: mat                !< *MAT_ELASTIC parameters
    integer, intent(in) :: n                            !< points in the block (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS             !< leading dimension
    real(wp), intent(in) :: f(ld, 9)                    !< deformation gradients F_{n+1}
    real(wp), intent(in) :: j(ld)                       !< their determinants
    real(wp), intent(out) :: tau(ld, 6)                 !< Kirchhoff stresses
    logical, intent(out) :: ok(ld)                      !< point updated
    real(wp) :: lambda, mu, log_j(ld), pressure
    integer :: i
    call lame_constants(mat%young, mat%poisson, lambda, mu)
    do i = 1, n
      ok(i) = j(i) > 0.0_wp
    end do
    do i = 1, n
      log_j(i) = natural_log(merge(j(i), 1.0_wp, ok(i)))
    end do
    ! b = F F^T (F(a, m) = f(i, a + 3 (m - 1))), tau = mu (b - 1) + lambda ln J 1
    do i = 1, n
      pressure = lambda*log_j(i)
      tau(i, 1) = mu*((f(i, 1)*f(i, 1) + f(i, 4)*f(i, 4) + f(i, 7)*f(i, 7)) - 1.0_wp) + pressure
      tau(i, 2) = mu*((f(i, 2)*f(i, 2) + f(i, 5)*f(i, 5) + f(i, 8)*f(i, 8)) - 1.0_wp) + pressure
      tau(i, 3) = mu*((f(i, 3)*f(i, 3) + f(i, 6)*f(i, 6) + f(i, 9)*f(i, 9)) - 1.0_wp) + pressure
      tau(i, 4) = mu*(f(i, 1)*f(i, 2) + f(i, 4)*f(i, 5) + f(i, 7)*f(i, 8))
      tau(i, 5) = mu*(f(i, 2)*f(i, 3) + f(i, 5)*f(i, 6) + f(i, 8)*f(i, 9))
      tau(i, 6) = mu*(f(i, 1)*f(i, 3) + f(i, 4)*f(i, 6) + f(i, 7)*f(i, 9))
    end do
    do i = 1, n
      if (.not. ok(i)) tau(i, :) = 0.0_wp
    end do
  end subroutine mat_elastic_update_block

end module mefem_mat_elastic
