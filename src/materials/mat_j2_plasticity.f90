!> Finite-strain J2 plasticity with isotropic hardening: Simo's multiplicative, hyperelastic-
!> based return map (Simo 1992; Simo & Hughes 1998, Boxes 9.1 and 9.2; formulation.md 6.1-6.2),
!> used for *MAT_PIECEWISE_LINEAR_PLASTICITY (*MAT_024) and *MAT_POWER_LAW_PLASTICITY
!> (*MAT_018); the hardening law K(alpha) comes from mefem_hardening. The same update with a
!> back stress (mixed isotropic-kinematic hardening) for *MAT_PLASTIC_KINEMATIC (*MAT_003):
!> mat_j2_kinematic_update.
!>
!> Free energy: W = U(J) + mu/2 (tr be_bar - 3), U(J) = kappa/2 (1/2 (J^2 - 1) - ln J),
!> mu = E/(2(1+nu)), kappa = E/(3(1-2nu)). Yield function |s| - sqrt(2/3) K(alpha) on the
!> Kirchhoff deviator s (so the von Mises value of tau equals K). Steps, with F = F_{n+1}:
!>   1-2 be_tr = J^{-2/3} F Cbar_p,n^{-1} F^T (= f_bar be_bar_n f_bar^T with f = F F_n^{-1},
!>     f_bar = det(f)^{-1/3} f, as Cbar_p,n^{-1} = J_n^{2/3} F_n^{-1} be_bar_n F_n^{-T} is
!>     what the history keeps: mefem_material_state); s_tr = mu dev(be_tr);
!>     I_bar = tr(be_tr)/3; mu_bar = mu I_bar
!>   3 f_tr = |s_tr| - sqrt(2/3) K(alpha_n)
!>   4 f_tr <= 0: elastic, s = s_tr. Else n = s_tr/|s_tr| and dgamma solves
!>     r = |s_tr| - 2 mu_bar dgamma - sqrt(2/3) K(alpha_n + sqrt(2/3) dgamma) = 0
!>     (Newton safeguarded by bisection on the bracket [0, |s_tr|/(2 mu_bar)]);
!>     s = s_tr - 2 mu_bar dgamma n, alpha_{n+1} = alpha_n + sqrt(2/3) dgamma
!>   5 be_bar_{n+1} = s/mu + x 1 with x the root near I_bar of det(s/mu + x 1) = 1, so that
!>     det be_bar = 1 holds to round-off at every step (plastic flow exactly isochoric; S&H's
!>     x = I_bar keeps it only to first order). The stress of this step does not depend on x.
!>   6 tau = J U'(J) 1 + s = kappa/2 (J^2 - 1) 1 + s
!>   7 history: Cbar_p^{-1} = J^{2/3} F^{-1} be_bar_{n+1} F^{-T} = J^{-4/3} adj(F) be_bar adj(F)^T
!>     (det = 1 as det be_bar = 1), alpha_{n+1}
!> Tangent (c of L_v tau = c : d, derived for this algorithm; it is S&H Box 9.2):
!>   c = kappa J^2 1(x)1 - kappa (J^2 - 1) I + (1 - beta1) c_tr
!>       - 2 mu_bar beta3 n(x)n - 2 mu_bar beta4 n(x)dev(n^2)
!>   c_tr = 2 mu_bar (I - 1/3 1(x)1) - 2/3 (s_tr(x)1 + 1(x)s_tr)
!>   beta0 = 1 + K'/(3 mu_bar), beta1 = 2 mu_bar dgamma/|s_tr|,
!>   beta2 = (1 - 1/beta0) 2/3 |s_tr|/mu_bar dgamma, beta3 = 1/beta0 - beta1 + beta2,
!>   beta4 = (1/beta0 - beta1) |s_tr|/mu_bar       (elastic step: beta1 = beta3 = beta4 = 0)
!> The last term makes c unsymmetric (major symmetry) in plastic steps; it is the exact
!> linearisation (checked against finite differences in tests/unit/test_materials.f90). A
!> symmetric solver may use (c_ijkl + c_klij)/2 at the cost of the quadratic rate.
!> Wave speed: c = sqrt((kappa + 4/3 mu_bar)/rho0), the elastic longitudinal modulus of c
!> (kappa J^2 - kappa (J^2 - 1) = kappa exactly for this U) per reference volume; since
!> I_bar >= 1 for det be_bar = 1 it is never below the small-strain sqrt((K + 4/3 G)/rho0).
module mefem_mat_j2_plasticity
  use mefem_kinds, only: wp
  use mefem_model, only: material_t, curve_t
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa, rtoa
  use mefem_tensor_algebra, only: IDENTITY, inverse_cube_root, CUBE_ROOT_SERIES_RANGE, &
                                  C1 => CUBE_ROOT_C1, C2 => CUBE_ROOT_C2, C3 => CUBE_ROOT_C3, &
                                  deviator, add_outer_product, add_symmetric_identity
  use mefem_material_state, only: NHIST, HIST_CP, HIST_ALPHA, HIST_BACK, BLOCK_POINTS
  use mefem_hardening, only: hardening_yield, hardening_yield_block
  implicit none
  private

  public :: mat_j2_update, mat_j2_update_block, mat_j2_kinematic_update, &
            mat_j2_kinematic_update_block

  real(wp), parameter :: SQRT_TWO_THIRDS = sqrt(2.0_wp/3.0_wp)
  real(wp), parameter :: ONE_THIRD = 1.0_wp/3.0_wp       !< (products instead of divisions)
  real(wp), parameter :: RETURN_TOLERANCE = 1.0e-13_wp   !< |r| relative to |s_tr|
  integer, parameter :: MAX_RETURN_ITERATIONS = 100       !< Newton/bisection steps
  !> |det - 1| of the unimodular shift's cubic taken as round-off
  real(wp), parameter :: SHIFT_TOLERANCE = 4.0_wp*epsilon(1.0_wp)
  !> Symmetric tensors as 6 components, in the Voigt order of the history (mefem_material_state)
  integer, parameter :: XX = 1, YY = 2, ZZ = 3, XY = 4, YZ = 5, ZX = 6, SYM = 6

contains

  !> Stress, history, wave speed and (optionally) consistent tangent at F_{n+1}.
  !> Hot path of the explicit solver: symmetric tensors are held as their 6 components and
  !> every 3x3 operation is written out here (inlined), without array temporaries; the history
  !> is read and written through the offsets of mefem_material_state. The 3x3 tensors of the
  !> tangent are built only when c_tau is asked for.
  pure subroutine mat_j2_update(mat, curves, law, f_new, hist_old, hist_new, tau, sound_speed, &
                                status, c_tau, rate_factor, committed)
    type(material_t), intent(in) :: mat                !< *MAT_024 / *MAT_018 parameters
    type(curve_t), intent(in) :: curves(:)              !< the model's curves (for LCSS)
    integer, intent(in) :: law                          !< HARDENING_* of mefem_hardening
    real(wp), intent(in) :: f_new(3,3)                  !< deformation gradient F_{n+1}
    real(wp), intent(in) :: hist_old(NHIST)             !< history at t_n
    real(wp), intent(out) :: hist_new(NHIST)            !< history at t_{n+1}
    real(wp), intent(out) :: tau(3,3)                   !< Kirchhoff stress
    real(wp), intent(out) :: sound_speed                !< dilatational wave speed
    type(status_t), intent(out) :: status               !< det F <= 0, no convergence
    real(wp), intent(out), optional :: c_tau(3,3,3,3)   !< spatial tangent of tau
    real(wp), intent(in), optional :: rate_factor       !< yield stress scale of the strain
                                                        !< rate (hardening_rate_factor; 1)
    logical, intent(in), optional :: committed          !< hist_old is F's own (output): its
                                                        !< stress, no yield check
    real(wp) :: mu, kappa, j, adj(3,3), factor_rate
    real(wp) :: s_trial(SYM), s(SYM), be_new(SYM)
    real(wp) :: i_bar, mu_bar, norm_trial, alpha_old, alpha_new, yield_old, slope, dgamma
    real(wp) :: jp, scale, return_factor, factor
    real(wp) :: beta0, beta1, beta2, beta3, beta4
    real(wp) :: normal(3,3), s_trial_full(3,3)
    integer :: k
    logical :: plastic, converged
    hist_new = hist_old
    tau = 0.0_wp
    sound_speed = 0.0_wp
    if (present(c_tau)) c_tau = 0.0_wp
    j = det3(f_new)
    if (.not. (j > 0.0_wp)) then
      call fail(status, mat, 'det F = '//rtoa(j)//' <= 0 (inverted or degenerate element)')
      return
    end if
    mu = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
    kappa = mat%young/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
    ! 1-2: the elastic trial state
    call elastic_trial(f_new, j, hist_old(HIST_CP:HIST_CP + 5), mu, scale, i_bar, mu_bar, &
                       s_trial)
    norm_trial = sym_norm(s_trial)
    ! 3-4: yield check and return map
    alpha_old = hist_old(HIST_ALPHA)
    factor_rate = 1.0_wp
    if (present(rate_factor)) factor_rate = rate_factor
    call hardening_yield(law, mat, curves, alpha_old, yield_old, slope)
    yield_old = factor_rate*yield_old
    slope = factor_rate*slope
    if (.not. (yield_old > 0.0_wp)) then
      call fail(status, mat, 'yield stress '//rtoa(yield_old)//' <= 0 at plastic strain '// &
                rtoa(alpha_old))
      return
    end if
    plastic = norm_trial - SQRT_TWO_THIRDS*yield_old > 0.0_wp
    if (present(committed)) plastic = plastic .and. .not. committed
    dgamma = 0.0_wp
    alpha_new = alpha_old
    s = s_trial
    if (plastic) then
      call return_map(law, mat, curves, factor_rate, alpha_old, yield_old, norm_trial, &
                      mu_bar, dgamma, slope, converged)
      if (.not. converged) then
        call fail(status, mat, 'J2 return map did not converge (trial von Mises stress '// &
                  rtoa(sqrt(1.5_wp)*norm_trial)//', yield stress '//rtoa(yield_old)//')')
        return
      end if
      ! s = s_tr - 2 mu_bar dgamma n, n = s_tr/|s_tr|
      return_factor = 1.0_wp - 2.0_wp*mu_bar*dgamma/norm_trial
      s = return_factor*s_trial
      alpha_new = alpha_old + SQRT_TWO_THIRDS*dgamma
    end if
    ! 5: elastic strain with det = 1
    be_new = s*(1.0_wp/mu)
    call unimodular_shift(be_new, i_bar)
    ! 6: Kirchhoff stress
    jp = 0.5_wp*kappa*(j*j - 1.0_wp)
    call sym_to_full(s, tau)
    do k = 1, 3
      tau(k, k) = tau(k, k) + jp
    end do
    ! 7: history, Cbar_p^-1 = J^(-4/3) adj(F) be_bar adj(F)^T
    call adjugate(f_new, adj)
    call symmetric_sandwich(adj, be_new, scale*scale, hist_new(HIST_CP:HIST_CP + 5))
    hist_new(HIST_ALPHA) = alpha_new
    sound_speed = sqrt((kappa + 4.0_wp/3.0_wp*mu_bar)/mat%density)
    if (.not. present(c_tau)) return
    ! consistent tangent
    call sym_to_full(s_trial, s_trial_full)
    call add_outer_product(c_tau, kappa*j*j, IDENTITY, IDENTITY)
    call add_symmetric_identity(c_tau, -2.0_wp*jp)
    factor = 1.0_wp
    if (plastic) then
      beta0 = 1.0_wp + slope/(3.0_wp*mu_bar)
      beta1 = 2.0_wp*mu_bar*dgamma/norm_trial
      beta2 = (1.0_wp - 1.0_wp/beta0)*2.0_wp/3.0_wp*norm_trial/mu_bar*dgamma
      beta3 = 1.0_wp/beta0 - beta1 + beta2
      beta4 = (1.0_wp/beta0 - beta1)*norm_trial/mu_bar
      factor = 1.0_wp - beta1
      normal = s_trial_full/norm_trial
      call add_outer_product(c_tau, -2.0_wp*mu_bar*beta3, normal, normal)
      call add_outer_product(c_tau, -2.0_wp*mu_bar*beta4, normal, &
                             deviator(matmul(normal, normal)))
    end if
    call add_symmetric_identity(c_tau, factor*2.0_wp*mu_bar)
    call add_outer_product(c_tau, -factor*2.0_wp*mu_bar/3.0_wp, IDENTITY, IDENTITY)
    call add_outer_product(c_tau, -factor*2.0_wp/3.0_wp, s_trial_full, IDENTITY)
    call add_outer_product(c_tau, -factor*2.0_wp/3.0_wp, IDENTITY, s_trial_full)
  end subroutine mat_j2_update

  !> The explicit update of a block of n points of one material (no tangent, no wave speed):
  !> the steps of mat_j2_update with the points in the inner loops, structure-of-arrays
  !> (entry i of every array is point i), so that the compiler vectorises across points.
  !> Each point's arithmetic is mat_j2_update's, operation for operation (same bits).
  !> The hardening law, the return map of plastic points, the rare unimodular shifts that
  !> need Newton steps and the cube root outside the series range run point by point.
  !> A point that fails (det F <= 0, yield stress <= 0, no convergence) gets ok(i) = .false.
  !> and keeps its history (the caller calls mat_j2_update on it for the message).
  !> f(i, 1:9): F_{n+1} column by column; j(i) = det F_{n+1} (the caller's, same expression);
  !> hist(i, :): history at t_n in, at t_{n+1} out (points that fail: unchanged);
  !> tau(i, 1:6): Kirchhoff stress XX YY ZZ XY YZ ZX.
  subroutine mat_j2_update_block(mat, curves, law, n, f, j, hist, tau, ok, rate_factor)
    type(material_t), intent(in) :: mat                !< *MAT_024 / *MAT_018 parameters
    type(curve_t), intent(in) :: curves(:)              !< the model's curves (for LCSS)
    integer, intent(in) :: law                          !< HARDENING_* of mefem_hardening
    integer, intent(in) :: n                            !< points in the block (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS             !< leading dimension
    real(wp), intent(in) :: f(ld, 9)                    !< deformation gradients F_{n+1}
    real(wp), intent(in) :: j(ld)                       !< their determinants
    real(wp), intent(inout) :: hist(ld, NHIST)          !< histories t_n -> t_{n+1}
    real(wp), intent(out) :: tau(ld, SYM)               !< Kirchhoff stresses
    logical, intent(out) :: ok(ld)                      !< point updated
    real(wp), intent(in), optional :: rate_factor(ld)   !< yield stress scales (1)
    real(wp) :: mu, kappa, inverse_mu, factor_rate(ld)
    real(wp), dimension(ld) :: x, d, scale, i_bar, mu_bar, norm_trial, yield_old
    real(wp), dimension(ld) :: slope, dgamma, i2, i3, g, jp, denominator
    real(wp), dimension(ld) :: residual0, step, alpha_step, yield_step, slope_step
    real(wp) :: high, derivative, residual1
    integer :: plastic_point(ld), nplastic
    real(wp) :: adj(9), tt(9), cp(SYM), be_trial(SYM), s(SYM), dv(SYM), factor
    real(wp) :: s_trial(ld, SYM), be_new(ld, SYM), dev(ld, SYM), return_factor, x_shift(ld)
    real(wp) :: cp_new(ld, SYM)
    real(wp) :: x0, x1, x2, dg0, dg1, g1, g2
    logical :: plastic(ld), converged, shifted(ld)
    integer :: i, k
    mu = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
    kappa = mat%young/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
    inverse_mu = 1.0_wp/mu
    ! which points can be updated, and scale = J^(-2/3) as inverse_cube_root computes it (a 1
    ! in place of a J <= 0)
    do i = 1, n
      ok(i) = j(i) > 0.0_wp
      x(i) = merge(j(i), 1.0_wp, ok(i))
      d(i) = x(i) - 1.0_wp
      scale(i) = 1.0_wp + d(i)*(C1 + d(i)*(C2 + d(i)*C3))
      scale(i) = scale(i)*(4.0_wp - x(i)*(scale(i)*scale(i)*scale(i)))*ONE_THIRD
      scale(i) = scale(i)*(4.0_wp - x(i)*(scale(i)*scale(i)*scale(i)))*ONE_THIRD
    end do
    ! cube root outside the series range: inverse_cube_root's scalar pow, a call the compiler
    ! does not vectorise (written as ** here, gfortran used libmvec's vector pow, whose last
    ! bits differ from libm's, so a point's bits depended on its place in the block)
    do i = 1, n
      if (ok(i) .and. .not. abs(d(i)) <= CUBE_ROOT_SERIES_RANGE) &
        scale(i) = inverse_cube_root(x(i))
    end do
    ! 1-2: elastic trial state (as mat_j2_update: symmetric_sandwich written out, with f(i, :)
    ! column by column, f(i, 1) = F11, f(i, 2) = F21 ..)
    do i = 1, n
      scale(i) = scale(i)*scale(i)
      cp = hist(i, HIST_CP:HIST_CP + 5)
      do k = 1, 3                              ! tt(k, :) = F(k, :) Cbar_p^-1
        tt(k) = f(i, k)*cp(XX) + f(i, k + 3)*cp(XY) + f(i, k + 6)*cp(ZX)
        tt(k + 3) = f(i, k)*cp(XY) + f(i, k + 3)*cp(YY) + f(i, k + 6)*cp(YZ)
        tt(k + 6) = f(i, k)*cp(ZX) + f(i, k + 3)*cp(YZ) + f(i, k + 6)*cp(ZZ)
      end do
      be_trial(XX) = scale(i)*(tt(1)*f(i, 1) + tt(4)*f(i, 4) + tt(7)*f(i, 7))
      be_trial(YY) = scale(i)*(tt(2)*f(i, 2) + tt(5)*f(i, 5) + tt(8)*f(i, 8))
      be_trial(ZZ) = scale(i)*(tt(3)*f(i, 3) + tt(6)*f(i, 6) + tt(9)*f(i, 9))
      be_trial(XY) = scale(i)*(tt(1)*f(i, 2) + tt(4)*f(i, 5) + tt(7)*f(i, 8))
      be_trial(YZ) = scale(i)*(tt(2)*f(i, 3) + tt(5)*f(i, 6) + tt(8)*f(i, 9))
      be_trial(ZX) = scale(i)*(tt(3)*f(i, 1) + tt(6)*f(i, 4) + tt(9)*f(i, 7))
      i_bar(i) = (be_trial(XX) + be_trial(YY) + be_trial(ZZ))*ONE_THIRD
      mu_bar(i) = mu*i_bar(i)
      s_trial(i, XX:ZZ) = mu*(be_trial(XX:ZZ) - i_bar(i))
      s_trial(i, XY:ZX) = mu*be_trial(XY:ZX)
      norm_trial(i) = sqrt(s_trial(i, XX)*s_trial(i, XX) + s_trial(i, YY)*s_trial(i, YY) + &
                           s_trial(i, ZZ)*s_trial(i, ZZ) + 2.0_wp*(s_trial(i, XY)*s_trial(i, XY) &
                           + s_trial(i, YZ)*s_trial(i, YZ) + s_trial(i, ZX)*s_trial(i, ZX)))
    end do
    ! 3-4: yield check (the hardening law for the whole block) and return map of the plastic
    ! points (points that cannot be updated are neither: their alpha_n is not used)
    call hardening_yield_block(law, mat, curves, n, hist(:, HIST_ALPHA), yield_old, slope)
    if (present(rate_factor)) then
      factor_rate(1:n) = rate_factor(1:n)
      do i = 1, n
        yield_old(i) = factor_rate(i)*yield_old(i)
        slope(i) = factor_rate(i)*slope(i)
      end do
    else
      factor_rate(1:n) = 1.0_wp
    end if
    do i = 1, n
      ok(i) = ok(i) .and. yield_old(i) > 0.0_wp
      plastic(i) = ok(i) .and. norm_trial(i) - SQRT_TWO_THIRDS*yield_old(i) > 0.0_wp
      dgamma(i) = 0.0_wp
      denominator(i) = merge(norm_trial(i), 1.0_wp, plastic(i))
    end do
    ! return_map's first two iterations for the block's plastic points at once (the same
    ! values: its residual at dgamma = 0, one Newton step kept inside (0, |s_tr|/(2 mu_bar))
    ! or else the bracket's midpoint, the residual there with the hardening law of the
    ! block); the points these do not settle take return_map itself (a piecewise linear law
    ! is settled by the step unless it crosses a table point)
    nplastic = 0
    do i = 1, n
      if (.not. plastic(i)) cycle
      nplastic = nplastic + 1
      plastic_point(nplastic) = i
    end do
    do k = 1, nplastic
      i = plastic_point(k)
      residual0(k) = norm_trial(i) - SQRT_TWO_THIRDS*yield_old(i)
      high = norm_trial(i)/(2.0_wp*mu_bar(i))
      derivative = -2.0_wp*mu_bar(i) - 2.0_wp/3.0_wp*slope(i)
      step(k) = merge(-residual0(k)/merge(derivative, -1.0_wp, derivative < 0.0_wp), high, &
                      derivative < 0.0_wp)
      if (.not. (step(k) > 0.0_wp .and. step(k) < high)) step(k) = 0.5_wp*high
      alpha_step(k) = hist(i, HIST_ALPHA) + SQRT_TWO_THIRDS*step(k)
    end do
    call hardening_yield_block(law, mat, curves, nplastic, alpha_step, yield_step, slope_step)
    if (present(rate_factor)) then
      do k = 1, nplastic
        yield_step(k) = factor_rate(plastic_point(k))*yield_step(k)
        slope_step(k) = factor_rate(plastic_point(k))*slope_step(k)
      end do
    end if
    do k = 1, nplastic
      i = plastic_point(k)
      residual1 = norm_trial(i) - 2.0_wp*mu_bar(i)*step(k) - SQRT_TWO_THIRDS*yield_step(k)
      if (abs(residual0(k)) <= RETURN_TOLERANCE*norm_trial(i)) then
        dgamma(i) = 0.0_wp                     ! (barely plastic: settled at dgamma = 0)
      else if (abs(residual1) <= RETURN_TOLERANCE*norm_trial(i)) then
        dgamma(i) = step(k)
        slope(i) = slope_step(k)
      else
        call return_map(law, mat, curves, factor_rate(i), hist(i, HIST_ALPHA), yield_old(i), &
                        norm_trial(i), &
                        mu_bar(i), dgamma(i), slope(i), converged)
        ok(i) = converged
      end if
    end do
    ! 5: s, be_new = s/mu, the unimodular shift's first test, tau (branch-free: elastic points
    ! have dgamma = 0, so return_factor = 1 and s = s_trial exactly)
    do i = 1, n
      return_factor = 1.0_wp - 2.0_wp*mu_bar(i)*dgamma(i)/denominator(i)
      s = return_factor*s_trial(i, :)
      be_new(i, :) = s*inverse_mu
      dv = be_new(i, :)
      dv(XX:ZZ) = dv(XX:ZZ) - (be_new(i, XX) + be_new(i, YY) + be_new(i, ZZ))*ONE_THIRD
      i2(i) = -0.5_wp*(dv(XX)*dv(XX) + dv(YY)*dv(YY) + dv(ZZ)*dv(ZZ) + &
                       2.0_wp*(dv(XY)*dv(XY) + dv(YZ)*dv(YZ) + dv(ZX)*dv(ZX)))
      i3(i) = dv(XX)*(dv(YY)*dv(ZZ) - dv(YZ)*dv(YZ)) - dv(XY)*(dv(XY)*dv(ZZ) - dv(YZ)*dv(ZX)) &
            + dv(ZX)*(dv(XY)*dv(YZ) - dv(YY)*dv(ZX))
      g(i) = (i_bar(i)*i_bar(i) + i2(i))*i_bar(i) + i3(i) - 1.0_wp
      dev(i, :) = dv
      jp(i) = 0.5_wp*kappa*(j(i)*j(i) - 1.0_wp)
      tau(i, XX:ZZ) = s(XX:ZZ) + jp(i)
      tau(i, XY:ZX) = s(XY:ZX)
    end do
    ! unimodular_shift's test at x0 = I_bar and its first two Newton steps for the whole block
    ! (branch-free, the same arithmetic, so the same bits; a step with dg <= 0 is not taken);
    ! the points these do not settle take unimodular_shift itself
    do i = 1, n
      x0 = i_bar(i)
      dg0 = 3.0_wp*x0*x0 + i2(i)
      x1 = x0 - g(i)/merge(dg0, 1.0_wp, dg0 > 0.0_wp)
      g1 = (x1*x1 + i2(i))*x1 + i3(i) - 1.0_wp
      dg1 = 3.0_wp*x1*x1 + i2(i)
      x2 = x1 - g1/merge(dg1, 1.0_wp, dg1 > 0.0_wp)
      g2 = (x2*x2 + i2(i))*x2 + i3(i) - 1.0_wp
      shifted(i) = .true.
      if (abs(g(i)) <= SHIFT_TOLERANCE) then
        x_shift(i) = x0
      else if (dg0 > 0.0_wp .and. abs(g1) <= SHIFT_TOLERANCE) then
        x_shift(i) = x1
      else if (dg0 > 0.0_wp .and. dg1 > 0.0_wp .and. abs(g2) <= SHIFT_TOLERANCE) then
        x_shift(i) = x2
      else
        shifted(i) = .false.
        x_shift(i) = x0
      end if
    end do
    do i = 1, n
      if (shifted(i)) then
        be_new(i, :) = dev(i, :)
        be_new(i, XX:ZZ) = dev(i, XX:ZZ) + x_shift(i)
      else if (ok(i)) then
        call unimodular_shift(be_new(i, :), i_bar(i))
      end if
    end do
    ! 7: the new history, Cbar_p^-1 = J^(-4/3) adj(F) be_bar adj(F)^T (as mat_j2_update: the
    ! adjugate's and symmetric_sandwich's expressions, adj column by column); elastic points
    ! have dgamma = 0, alpha_n + 0 = alpha_n; a block with a failed point takes the (rare) loop
    ! that leaves that point's history as it was
    do i = 1, n
      adj(1) = f(i, 5)*f(i, 9) - f(i, 8)*f(i, 6)
      adj(4) = f(i, 7)*f(i, 6) - f(i, 4)*f(i, 9)
      adj(7) = f(i, 4)*f(i, 8) - f(i, 7)*f(i, 5)
      adj(2) = f(i, 8)*f(i, 3) - f(i, 2)*f(i, 9)
      adj(5) = f(i, 1)*f(i, 9) - f(i, 7)*f(i, 3)
      adj(8) = f(i, 7)*f(i, 2) - f(i, 1)*f(i, 8)
      adj(3) = f(i, 2)*f(i, 6) - f(i, 5)*f(i, 3)
      adj(6) = f(i, 4)*f(i, 3) - f(i, 1)*f(i, 6)
      adj(9) = f(i, 1)*f(i, 5) - f(i, 4)*f(i, 2)
      do k = 1, 3                              ! tt(k, :) = adj(k, :) be_bar
        tt(k) = adj(k)*be_new(i, XX) + adj(k + 3)*be_new(i, XY) + adj(k + 6)*be_new(i, ZX)
        tt(k + 3) = adj(k)*be_new(i, XY) + adj(k + 3)*be_new(i, YY) + adj(k + 6)*be_new(i, YZ)
        tt(k + 6) = adj(k)*be_new(i, ZX) + adj(k + 3)*be_new(i, YZ) + adj(k + 6)*be_new(i, ZZ)
      end do
      factor = scale(i)*scale(i)
      cp_new(i, XX) = factor*(tt(1)*adj(1) + tt(4)*adj(4) + tt(7)*adj(7))
      cp_new(i, YY) = factor*(tt(2)*adj(2) + tt(5)*adj(5) + tt(8)*adj(8))
      cp_new(i, ZZ) = factor*(tt(3)*adj(3) + tt(6)*adj(6) + tt(9)*adj(9))
      cp_new(i, XY) = factor*(tt(1)*adj(2) + tt(4)*adj(5) + tt(7)*adj(8))
      cp_new(i, YZ) = factor*(tt(2)*adj(3) + tt(5)*adj(6) + tt(8)*adj(9))
      cp_new(i, ZX) = factor*(tt(3)*adj(1) + tt(6)*adj(4) + tt(9)*adj(7))
    end do
    if (all(ok(1:n))) then
      do i = 1, n
        do k = 0, 5
          hist(i, HIST_CP + k) = cp_new(i, 1 + k)
        end do
        hist(i, HIST_ALPHA) = hist(i, HIST_ALPHA) + SQRT_TWO_THIRDS*dgamma(i)
      end do
    else
      do i = 1, n
        if (.not. ok(i)) cycle
        hist(i, HIST_CP:HIST_CP + 5) = cp_new(i, :)
        hist(i, HIST_ALPHA) = hist(i, HIST_ALPHA) + SQRT_TWO_THIRDS*dgamma(i)
      end do
    end if
  end subroutine mat_j2_update_block

  !> Plastic multiplier dgamma of the return map: root of
  !> r = |s_tr| - 2 mu_bar dgamma - sqrt(2/3) K(alpha_n + sqrt(2/3) dgamma) in
  !> (0, |s_tr|/(2 mu_bar)) by Newton steps, replaced by bisection when they leave the bracket.
  pure subroutine return_map(law, mat, curves, factor_rate, alpha_old, yield_old, norm_trial, &
                             mu_bar, dgamma, slope, converged)
    integer, intent(in) :: law                 !< HARDENING_*
    type(material_t), intent(in) :: mat        !< material parameters
    type(curve_t), intent(in) :: curves(:)     !< the model's curves
    real(wp), intent(in) :: factor_rate        !< yield scale of the strain rate (1: none)
    real(wp), intent(in) :: alpha_old          !< alpha_n
    real(wp), intent(in) :: yield_old          !< K(alpha_n) (the yield check's)
    real(wp), intent(in) :: norm_trial         !< |s_tr| (> sqrt(2/3) K(alpha_n))
    real(wp), intent(in) :: mu_bar             !< mu I_bar
    real(wp), intent(out) :: dgamma            !< plastic multiplier
    real(wp), intent(inout) :: slope           !< in: K'(alpha_n) (the yield check's);
                                               !< out: K' at alpha_n + sqrt(2/3) dgamma
    logical, intent(out) :: converged          !< |r| <= RETURN_TOLERANCE |s_tr|
    real(wp) :: low, high, residual, derivative, next, yield_stress
    integer :: iteration
    low = 0.0_wp
    high = norm_trial/(2.0_wp*mu_bar)
    dgamma = 0.0_wp
    converged = .false.
    yield_stress = yield_old                   ! the first iterate, dgamma = 0, is alpha_n
    do iteration = 1, MAX_RETURN_ITERATIONS
      if (iteration > 1) then
        call hardening_yield(law, mat, curves, alpha_old + SQRT_TWO_THIRDS*dgamma, &
                             yield_stress, slope)
        yield_stress = factor_rate*yield_stress
        slope = factor_rate*slope
      end if
      residual = norm_trial - 2.0_wp*mu_bar*dgamma - SQRT_TWO_THIRDS*yield_stress
      if (abs(residual) <= RETURN_TOLERANCE*norm_trial) then
        converged = .true.
        return
      end if
      if (residual > 0.0_wp) then
        low = dgamma
      else
        high = dgamma
      end if
      derivative = -2.0_wp*mu_bar - 2.0_wp/3.0_wp*slope
      if (derivative < 0.0_wp) then
        next = dgamma - residual/derivative
      else
        next = high
      end if
      if (.not. (next > low .and. next < high)) next = 0.5_wp*(low + high)
      dgamma = next
    end do
  end subroutine return_map

  !> *MAT_PLASTIC_KINEMATIC (MAT_003): bilinear J2 plasticity with mixed hardening, the steps
  !> of mat_j2_update with a back stress (doc/theory.md 4.4). Plastic modulus E_p = E ETAN /
  !> (E - ETAN), split by BETA into isotropic beta E_p and kinematic (1 - beta) E_p (Prager):
  !>   yield radius sqrt(2/3) (SIGY + beta E_p alpha) about the back stress b (a Kirchhoff
  !>   deviator); shifted trial xi_tr = s_tr - b_tr, n = xi_tr/|xi_tr|;
  !>   dgamma = (|xi_tr| - sqrt(2/3) (SIGY + beta E_p alpha_n)) / (2 mu_bar + 2/3 E_p) (linear
  !>   hardening: closed form); s = s_tr - 2 mu_bar dgamma n,
  !>   b = b_tr + 2/3 (1 - beta) E_p dgamma n, alpha += sqrt(2/3) dgamma.
  !> The back stress is kept in the frame that rotates with the material, b_hat = R^T b R with
  !> R the rotation of the polar decomposition F = R U (the Green-Naghdi rate: objective, and a
  !> stretch does not stretch the back stress, as a push-forward with F would), and brought to
  !> the current configuration as b_tr = R b_hat R^T. The tangent (implicit analyses) is the
  !> central difference of this update along the six symmetric directions h of dF = h F
  !> (c : h = D tau[h F] - h tau - tau h^T; step 1e-6): consistent to about 1e-9.
  pure subroutine mat_j2_kinematic_update(mat, f_new, hist_old, hist_new, tau, sound_speed, &
                                          status, c_tau, rate_factor, committed)
    type(material_t), intent(in) :: mat                !< *MAT_003 parameters
    real(wp), intent(in) :: f_new(3,3)                  !< deformation gradient F_{n+1}
    real(wp), intent(in) :: hist_old(NHIST)             !< history at t_n
    real(wp), intent(out) :: hist_new(NHIST)            !< history at t_{n+1}
    real(wp), intent(out) :: tau(3,3)                   !< Kirchhoff stress
    real(wp), intent(out) :: sound_speed                !< dilatational wave speed
    type(status_t), intent(out) :: status               !< det F <= 0
    real(wp), intent(out), optional :: c_tau(3,3,3,3)   !< spatial tangent of tau
    real(wp), intent(in), optional :: rate_factor       !< yield stress scale of the strain
                                                        !< rate (1)
    logical, intent(in), optional :: committed          !< hist_old is F's own (output)
    real(wp), parameter :: STEP = 1.0e-6_wp
    real(wp) :: h(3,3), tau_plus(3,3), tau_minus(3,3), scratch(NHIST), d_tau(3,3), dummy
    integer :: k, l
    type(status_t) :: probe
    real(wp) :: factor_rate
    logical :: elastic_only
    factor_rate = 1.0_wp
    if (present(rate_factor)) factor_rate = rate_factor
    elastic_only = .false.
    if (present(committed)) elastic_only = committed
    call kinematic_stress(mat, factor_rate, elastic_only, f_new, hist_old, hist_new, tau, &
                          sound_speed, status)
    if (.not. present(c_tau)) return
    c_tau = 0.0_wp
    if (.not. status%ok) return
    do l = 1, 3
      do k = 1, l
        h = 0.0_wp
        h(k, l) = 0.5_wp
        h(l, k) = h(l, k) + 0.5_wp
        call kinematic_stress(mat, factor_rate, elastic_only, f_new + STEP*matmul(h, f_new), &
                              hist_old, scratch, tau_plus, dummy, probe)
        call kinematic_stress(mat, factor_rate, elastic_only, f_new - STEP*matmul(h, f_new), &
                              hist_old, scratch, tau_minus, dummy, probe)
        d_tau = (tau_plus - tau_minus)/(2.0_wp*STEP) - matmul(h, tau) - matmul(tau, transpose(h))
        c_tau(:, :, k, l) = d_tau
        c_tau(:, :, l, k) = d_tau
      end do
    end do
  end subroutine mat_j2_kinematic_update

  !> The stress, history and wave speed of mat_j2_kinematic_update (no tangent).
  pure subroutine kinematic_stress(mat, factor_rate, elastic_only, f_new, hist_old, hist_new, &
                              tau, sound_speed, status, rotation)
    type(material_t), intent(in) :: mat                !< *MAT_003 parameters
    real(wp), intent(in) :: factor_rate                 !< yield scale of the strain rate
    logical, intent(in) :: elastic_only                 !< no yield check (committed stress)
    real(wp), intent(in) :: f_new(3,3)                  !< deformation gradient F_{n+1}
    real(wp), intent(in) :: hist_old(NHIST)             !< history at t_n
    real(wp), intent(out) :: hist_new(NHIST)            !< history at t_{n+1}
    real(wp), intent(out) :: tau(3,3)                   !< Kirchhoff stress
    real(wp), intent(out) :: sound_speed                !< dilatational wave speed
    type(status_t), intent(out) :: status               !< det F <= 0
    real(wp), intent(in), optional :: rotation(3,3)     !< R of F = R U, computed by the caller
                                                        !< (block_polar_rotation)
    real(wp) :: mu, kappa, j, scale, i_bar, mu_bar, norm_xi, plastic_modulus, yield_old, dgamma
    real(wp) :: jp, s_trial(SYM), back_trial(SYM), xi(SYM)
    real(wp) :: normal(SYM), s(SYM), back_new(SYM), be_new(SYM), adj(3,3), r(3,3)
    logical :: rotated
    integer :: k
    hist_new = hist_old
    tau = 0.0_wp
    sound_speed = 0.0_wp
    j = det3(f_new)
    if (.not. (j > 0.0_wp)) then
      call fail(status, mat, 'det F = '//rtoa(j)//' <= 0 (inverted or degenerate element)')
      return
    end if
    mu = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
    kappa = mat%young/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
    plastic_modulus = mat%young*mat%tangent_modulus/(mat%young - mat%tangent_modulus)
    ! elastic trial state (as mat_j2_update) and the back stress in the current frame (the
    ! polar rotation, an iteration, only where there is a back stress: none with BETA = 1,
    ! and none before a point first yields)
    call elastic_trial(f_new, j, hist_old(HIST_CP:HIST_CP + 5), mu, scale, i_bar, mu_bar, &
                       s_trial)
    rotated = any(hist_old(HIST_BACK:HIST_BACK + 5) /= 0.0_wp)
    if (present(rotation)) then
      r = rotation
      rotated = .true.
    end if
    if (rotated) then
      if (.not. present(rotation)) call polar_rotation(f_new, r)
      call symmetric_sandwich(r, hist_old(HIST_BACK:HIST_BACK + 5), 1.0_wp, back_trial)
    else
      back_trial = 0.0_wp
    end if
    xi = s_trial - back_trial
    norm_xi = sym_norm(xi)
    ! yield check and the closed-form return (linear hardening)
    ! (the strain rate scales the yield stress, SIGY + BETA Ep alpha, and its slope)
    yield_old = factor_rate*(mat%yield_stress + mat%beta*plastic_modulus*hist_old(HIST_ALPHA))
    s = s_trial
    back_new = back_trial
    if (norm_xi - SQRT_TWO_THIRDS*yield_old > 0.0_wp .and. .not. elastic_only) then
      if (mat%vp_dt > 0.0_wp) then        ! VP = 1: the yield radius of the plastic rate
        dgamma = kinematic_viscoplastic_dgamma(mat, norm_xi, mu_bar, plastic_modulus, &
                                               hist_old(HIST_ALPHA))
      else
        dgamma = (norm_xi - SQRT_TWO_THIRDS*yield_old)/(2.0_wp*mu_bar + 2.0_wp/3.0_wp* &
                 (factor_rate*mat%beta + 1.0_wp - mat%beta)*plastic_modulus)
      end if
      normal = xi/norm_xi
      s = s_trial - 2.0_wp*mu_bar*dgamma*normal
      back_new = back_trial + 2.0_wp/3.0_wp*(1.0_wp - mat%beta)*plastic_modulus*dgamma*normal
      hist_new(HIST_ALPHA) = hist_old(HIST_ALPHA) + SQRT_TWO_THIRDS*dgamma
    end if
    ! elastic strain with det = 1, Kirchhoff stress, history (as mat_j2_update)
    be_new = s*(1.0_wp/mu)
    call unimodular_shift(be_new, i_bar)
    jp = 0.5_wp*kappa*(j*j - 1.0_wp)
    call sym_to_full(s, tau)
    do k = 1, 3
      tau(k, k) = tau(k, k) + jp
    end do
    call adjugate(f_new, adj)
    call symmetric_sandwich(adj, be_new, scale*scale, hist_new(HIST_CP:HIST_CP + 5))
    if (any(back_new /= 0.0_wp)) then
      if (.not. rotated) call polar_rotation(f_new, r)
      call symmetric_sandwich(transpose(r), back_new, 1.0_wp, hist_new(HIST_BACK:HIST_BACK + 5))
    else
      hist_new(HIST_BACK:HIST_BACK + 5) = 0.0_wp
    end if
    sound_speed = sqrt((kappa + 4.0_wp/3.0_wp*mu_bar)/mat%density)
  end subroutine kinematic_stress

  !> The explicit update of a block of n *MAT_003 points (no tangent, no wave speed; VP = 0):
  !> kinematic_stress point by point without material_update's dispatch, the polar rotations
  !> of F of all points computed together where a back stress can exist (BETA < 1) by
  !> block_polar_rotation, whose iteration runs in the vector lanes. A point that fails
  !> (det F <= 0) gets ok(i) = .false. and keeps its history (the caller calls
  !> material_update on it for the message). f(i, 1:9): F_{n+1} column by column; j(i) =
  !> det F_{n+1}; hist(i, :): history at t_n in, t_{n+1} out; tau(i, 1:6): Kirchhoff stress XX
  !> YY ZZ XY YZ ZX.
  subroutine mat_j2_kinematic_update_block(mat, n, f, j, hist, tau, ok, rate_factor)
    type(material_t), intent(in) :: mat                !< *MAT_003 parameters (VP = 0)
    integer, intent(in) :: n                            !< points in the block (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS             !< leading dimension
    real(wp), intent(in) :: f(ld, 9)                    !< deformation gradients F_{n+1}
    real(wp), intent(in) :: j(ld)                       !< their determinants
    real(wp), intent(inout) :: hist(ld, NHIST)          !< histories t_n -> t_{n+1}
    real(wp), intent(out) :: tau(ld, SYM)               !< Kirchhoff stresses
    logical, intent(out) :: ok(ld)                      !< point updated
    real(wp), intent(in), optional :: rate_factor(ld)   !< yield stress scales (1)
    real(wp) :: rotation(ld, 9), f_point(3, 3), r_point(3, 3), tau_point(3, 3)
    real(wp) :: hist_new(NHIST), sound, factor
    type(status_t) :: status
    integer :: i, k
    do i = 1, n
      ok(i) = j(i) > 0.0_wp
    end do
    if (mat%beta < 1.0_wp) call block_polar_rotation(n, f, j, rotation)
    do i = 1, n
      if (.not. ok(i)) then
        tau(i, :) = 0.0_wp
        cycle
      end if
      do k = 1, 3
        f_point(:, k) = f(i, 3*k - 2:3*k)
        r_point(:, k) = rotation(i, 3*k - 2:3*k)
      end do
      factor = 1.0_wp
      if (present(rate_factor)) factor = rate_factor(i)
      if (mat%beta < 1.0_wp) then
        call kinematic_stress(mat, factor, .false., f_point, hist(i, :), hist_new, tau_point, &
                              sound, status, r_point)
      else
        call kinematic_stress(mat, factor, .false., f_point, hist(i, :), hist_new, tau_point, &
                              sound, status)
      end if
      ok(i) = status%ok
      tau(i, :) = [tau_point(1, 1), tau_point(2, 2), tau_point(3, 3), tau_point(1, 2), &
                   tau_point(2, 3), tau_point(3, 1)]
      if (ok(i)) hist(i, :) = hist_new
    end do
  end subroutine mat_j2_kinematic_update_block

  !> polar_rotation of n points, structure of arrays (m(i, r + 3 (c - 1)) = M(r, c)): Higham's
  !> scaled Newton iteration in the vector lanes, each lane taking polar_rotation's steps and
  !> stopping at its own convergence (a converged lane is no longer changed). Points with
  !> det F <= 0 get the identity.
  pure subroutine block_polar_rotation(n, f, det_f, r)
    integer, intent(in) :: n                            !< points (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS             !< leading dimension
    real(wp), intent(in) :: f(ld, 9)                    !< deformation gradients
    real(wp), intent(in) :: det_f(ld)                   !< their determinants
    real(wp), intent(out) :: r(ld, 9)                   !< their rotations
    real(wp), parameter :: IDENTITY9(9) = [1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, &
                                           0.0_wp, 0.0_wp, 1.0_wp]
    real(wp) :: x(ld, 9), t(ld, 9), det(ld), g(ld), change(ld), norm_r(ld), active(ld)
    integer :: i, k, iteration
    do k = 1, 9
      do i = 1, n
        x(i, k) = merge(f(i, k), IDENTITY9(k), det_f(i) > 0.0_wp)
        r(i, k) = IDENTITY9(k)
      end do
    end do
    do i = 1, n
      active(i) = merge(1.0_wp, 0.0_wp, det_f(i) > 0.0_wp)
    end do
    do iteration = 1, 50
      if (maxval(active(1:n)) == 0.0_wp) exit
      do i = 1, n
        ! x^-T = adj(x)^T / det(x) (adjugate's entries, transposed)
        t(i, 1) = x(i, 5)*x(i, 9) - x(i, 8)*x(i, 6)
        t(i, 2) = x(i, 7)*x(i, 6) - x(i, 4)*x(i, 9)
        t(i, 3) = x(i, 4)*x(i, 8) - x(i, 7)*x(i, 5)
        t(i, 4) = x(i, 8)*x(i, 3) - x(i, 2)*x(i, 9)
        t(i, 5) = x(i, 1)*x(i, 9) - x(i, 7)*x(i, 3)
        t(i, 6) = x(i, 7)*x(i, 2) - x(i, 1)*x(i, 8)
        t(i, 7) = x(i, 2)*x(i, 6) - x(i, 5)*x(i, 3)
        t(i, 8) = x(i, 4)*x(i, 3) - x(i, 1)*x(i, 6)
        t(i, 9) = x(i, 1)*x(i, 5) - x(i, 4)*x(i, 2)
        det(i) = x(i, 1)*(x(i, 5)*x(i, 9) - x(i, 8)*x(i, 6)) &
               - x(i, 4)*(x(i, 2)*x(i, 9) - x(i, 8)*x(i, 3)) &
               + x(i, 7)*(x(i, 2)*x(i, 6) - x(i, 5)*x(i, 3))
      end do
      do k = 1, 9
        do i = 1, n
          t(i, k) = t(i, k)/det(i)
        end do
      end do
      do i = 1, n
        g(i) = sqrt(sqrt(t(i, 1)**2 + t(i, 2)**2 + t(i, 3)**2 + t(i, 4)**2 + t(i, 5)**2 + &
                         t(i, 6)**2 + t(i, 7)**2 + t(i, 8)**2 + t(i, 9)**2)/ &
                    sqrt(x(i, 1)**2 + x(i, 2)**2 + x(i, 3)**2 + x(i, 4)**2 + x(i, 5)**2 + &
                         x(i, 6)**2 + x(i, 7)**2 + x(i, 8)**2 + x(i, 9)**2))
      end do
      do k = 1, 9
        do i = 1, n
          t(i, k) = 0.5_wp*(g(i)*x(i, k) + t(i, k)/g(i))        ! the new iterate
        end do
      end do
      do i = 1, n
        change(i) = sqrt((t(i, 1) - x(i, 1))**2 + (t(i, 2) - x(i, 2))**2 + &
                         (t(i, 3) - x(i, 3))**2 + (t(i, 4) - x(i, 4))**2 + &
                         (t(i, 5) - x(i, 5))**2 + (t(i, 6) - x(i, 6))**2 + &
                         (t(i, 7) - x(i, 7))**2 + (t(i, 8) - x(i, 8))**2 + &
                         (t(i, 9) - x(i, 9))**2)
        norm_r(i) = sqrt(t(i, 1)**2 + t(i, 2)**2 + t(i, 3)**2 + t(i, 4)**2 + t(i, 5)**2 + &
                         t(i, 6)**2 + t(i, 7)**2 + t(i, 8)**2 + t(i, 9)**2)
      end do
      do k = 1, 9
        do i = 1, n
          x(i, k) = merge(t(i, k), x(i, k), active(i) > 0.0_wp)
          r(i, k) = merge(t(i, k), r(i, k), active(i) > 0.0_wp)
        end do
      end do
      do i = 1, n
        active(i) = merge(0.0_wp, active(i), change(i) <= 1.0e-14_wp*norm_r(i))
      end do
    end do
  end subroutine block_polar_rotation

  !> *MAT_003 with VP = 1: the plastic multiplier of the return whose isotropic yield radius
  !> is R (SIGY + BETA Ep alpha), R = 1 + (rate_p/SRC)^(1/SRP) of the plastic strain rate
  !> rate_p = sqrt(2/3) dgamma/dt of the step (mat%vp_dt): the root of
  !> g = |xi_tr| - (2 mu_bar + 2/3 (1 - BETA) Ep) dgamma - sqrt(2/3) R (SIGY + BETA Ep alpha),
  !> which falls with dgamma from g(0) > 0 (the yield check) to g < 0 at |xi_tr|/(2 mu_bar):
  !> Newton steps kept inside the bracket (bisection where a step leaves it).
  pure real(wp) function kinematic_viscoplastic_dgamma(mat, norm_xi, mu_bar, plastic_modulus, &
                                                       alpha_old) result(dgamma)
    type(material_t), intent(in) :: mat                !< *MAT_003, vp_dt > 0, SRC > 0
    real(wp), intent(in) :: norm_xi                    !< |xi_tr|, trial relative stress
    real(wp), intent(in) :: mu_bar                     !< mu I_bar
    real(wp), intent(in) :: plastic_modulus            !< Ep
    real(wp), intent(in) :: alpha_old                  !< alpha_n
    integer, parameter :: MAX_ITERATIONS = 100
    !> relative residual of the root; fraction of SRC where the rate factor's slope is taken
    real(wp), parameter :: TOLERANCE = 1.0e-14_wp, RATE_FLOOR = 1.0e-12_wp
    real(wp) :: lo, hi, g, slope, rate, factor, factor_slope, radius, stiffness, next
    integer :: iteration
    stiffness = 2.0_wp*mu_bar + 2.0_wp/3.0_wp*(1.0_wp - mat%beta)*plastic_modulus
    lo = 0.0_wp
    hi = norm_xi/(2.0_wp*mu_bar)
    ! start: the rate-independent return (R = 1), which overshoots the root
    dgamma = min(hi, (norm_xi - SQRT_TWO_THIRDS*(mat%yield_stress + mat%beta*plastic_modulus* &
             alpha_old))/(stiffness + 2.0_wp/3.0_wp*mat%beta*plastic_modulus))
    do iteration = 1, MAX_ITERATIONS
      rate = SQRT_TWO_THIRDS*dgamma/mat%vp_dt
      factor = 1.0_wp + (rate/mat%cowper_c)**(1.0_wp/mat%cowper_p)
      factor_slope = (max(rate, RATE_FLOOR*mat%cowper_c)/mat%cowper_c)** &
                     (1.0_wp/mat%cowper_p - 1.0_wp)/(mat%cowper_p*mat%cowper_c)* &
                     SQRT_TWO_THIRDS/mat%vp_dt
      radius = mat%yield_stress + mat%beta*plastic_modulus*(alpha_old + SQRT_TWO_THIRDS*dgamma)
      g = norm_xi - stiffness*dgamma - SQRT_TWO_THIRDS*factor*radius
      if (abs(g) <= TOLERANCE*norm_xi) exit
      if (g > 0.0_wp) then
        lo = dgamma
      else
        hi = dgamma
      end if
      slope = -stiffness - SQRT_TWO_THIRDS*(factor_slope*radius + factor*mat%beta* &
                                            plastic_modulus*SQRT_TWO_THIRDS)
      next = dgamma - g/slope
      if (.not. (next > lo .and. next < hi)) next = 0.5_wp*(lo + hi)
      dgamma = next
    end do
  end function kinematic_viscoplastic_dgamma

  !> The elastic trial state of the update at F (det J > 0) from Cbar_p^-1 of t_n: be_tr =
  !> scale F Cbar_p^-1 F^T with scale = J^(-2/3) (upper triangle: exactly symmetric),
  !> I_bar = tr(be_tr)/3, mu_bar = mu I_bar and s_tr = mu dev(be_tr).
  pure subroutine elastic_trial(f, j, cp_old, mu, scale, i_bar, mu_bar, s_trial)
    real(wp), intent(in) :: f(3,3)        !< deformation gradient F_{n+1}
    real(wp), intent(in) :: j             !< det F
    real(wp), intent(in) :: cp_old(SYM)   !< Cbar_p^-1 of t_n
    real(wp), intent(in) :: mu            !< shear modulus
    real(wp), intent(out) :: scale        !< J^(-2/3)
    real(wp), intent(out) :: i_bar        !< tr(be_tr)/3
    real(wp), intent(out) :: mu_bar       !< mu I_bar
    real(wp), intent(out) :: s_trial(SYM) !< mu dev(be_tr)
    real(wp) :: be_trial(SYM)
    scale = inverse_cube_root(j)
    scale = scale*scale
    call symmetric_sandwich(f, cp_old, scale, be_trial)
    i_bar = (be_trial(XX) + be_trial(YY) + be_trial(ZZ))*ONE_THIRD
    mu_bar = mu*i_bar
    s_trial(XX:ZZ) = mu*(be_trial(XX:ZZ) - i_bar)
    s_trial(XY:ZX) = mu*be_trial(XY:ZX)
  end subroutine elastic_trial

  !> The rotation R of the polar decomposition F = R U (det F > 0): Higham's scaled Newton
  !> iteration X <- (g X + X^-T / g)/2, g = (|X^-1| / |X|)^(1/2) (Frobenius norms), from X = F,
  !> until X changes by less than 1e-14 of its norm (quadratic convergence: a few steps).
  pure subroutine polar_rotation(f, r)
    real(wp), intent(in) :: f(3,3)      !< deformation gradient (det > 0)
    real(wp), intent(out) :: r(3,3)     !< its rotation
    real(wp) :: x(3,3), adj(3,3), inverse_transpose(3,3), g, change
    integer :: iteration
    x = f
    do iteration = 1, 50
      call adjugate(x, adj)
      inverse_transpose = transpose(adj)/det3(x)
      g = sqrt(sqrt(sum(inverse_transpose**2))/sqrt(sum(x**2)))
      r = 0.5_wp*(g*x + inverse_transpose/g)
      change = sqrt(sum((r - x)**2))
      x = r
      if (change <= 1.0e-14_wp*sqrt(sum(r**2))) exit
    end do
  end subroutine polar_rotation

  !> Replace a by a + (x - tr(a)/3) 1 with x the root near x0 of det(dev(a) + x 1) = 1
  !> (Newton on the cubic x^3 + i2 x + i3 - 1, i2, i3 invariants of dev(a), until the cubic
  !> is within 4 eps of 0); if Newton fails, dev(a) + x0 1 is scaled by its det^(-1/3)
  !> instead. a: symmetric, 6 components.
  pure subroutine unimodular_shift(a, x0)
    real(wp), intent(inout) :: a(SYM)   !< symmetric tensor made unimodular (XX .. ZX)
    real(wp), intent(in) :: x0          !< starting value (the trace/3 wanted)
    real(wp) :: d(SYM), i2, i3, x, g, dg
    integer :: iteration
    d = a
    d(XX:ZZ) = d(XX:ZZ) - (a(XX) + a(YY) + a(ZZ))*ONE_THIRD
    i2 = -0.5_wp*sym_norm_squared(d)
    i3 = sym_det(d)
    x = x0
    do iteration = 1, 30
      g = (x*x + i2)*x + i3 - 1.0_wp
      if (abs(g) <= SHIFT_TOLERANCE) then          ! det = 1 to round-off (elastic steps:
        a = d                                       ! at once, x0 = I_bar)
        a(XX:ZZ) = a(XX:ZZ) + x
        return
      end if
      dg = 3.0_wp*x*x + i2
      if (.not. (dg > 0.0_wp)) exit
      x = x - g/dg
    end do
    a = d
    a(XX:ZZ) = a(XX:ZZ) + x0
    a = a*sym_det(a)**(-1.0_wp/3.0_wp)
  end subroutine unimodular_shift


  !> Determinant of a 3x3 matrix (the expression of mefem_tensor_algebra's determinant).
  pure real(wp) function det3(m)
    real(wp), intent(in) :: m(3,3)   !< the matrix
    det3 = m(1,1)*(m(2,2)*m(3,3) - m(2,3)*m(3,2)) &
         - m(1,2)*(m(2,1)*m(3,3) - m(2,3)*m(3,1)) &
         + m(1,3)*(m(2,1)*m(3,2) - m(2,2)*m(3,1))
  end function det3

  !> Adjugate (transposed cofactor matrix) of a 3x3 matrix: m adj(m) = det(m) 1.
  pure subroutine adjugate(m, adj)
    real(wp), intent(in) :: m(3,3)      !< the matrix
    real(wp), intent(out) :: adj(3,3)   !< its adjugate
    adj(1,1) = m(2,2)*m(3,3) - m(2,3)*m(3,2)
    adj(1,2) = m(1,3)*m(3,2) - m(1,2)*m(3,3)
    adj(1,3) = m(1,2)*m(2,3) - m(1,3)*m(2,2)
    adj(2,1) = m(2,3)*m(3,1) - m(2,1)*m(3,3)
    adj(2,2) = m(1,1)*m(3,3) - m(1,3)*m(3,1)
    adj(2,3) = m(1,3)*m(2,1) - m(1,1)*m(2,3)
    adj(3,1) = m(2,1)*m(3,2) - m(2,2)*m(3,1)
    adj(3,2) = m(1,2)*m(3,1) - m(1,1)*m(3,2)
    adj(3,3) = m(1,1)*m(2,2) - m(1,2)*m(2,1)
  end subroutine adjugate

  !> c = factor m a m^T for a symmetric a given by its 6 components (c likewise: the upper
  !> triangle, so exactly symmetric). The block kernel writes out the same expressions.
  pure subroutine symmetric_sandwich(m, a, factor, c)
    real(wp), intent(in) :: m(3,3)       !< the matrix
    real(wp), intent(in) :: a(SYM)       !< XX YY ZZ XY YZ ZX
    real(wp), intent(in) :: factor       !< scale of the product
    real(wp), intent(out) :: c(SYM)      !< factor m a m^T
    real(wp) :: t(3,3)
    integer :: r
    do r = 1, 3                          ! t = m a
      t(r, 1) = m(r, 1)*a(XX) + m(r, 2)*a(XY) + m(r, 3)*a(ZX)
      t(r, 2) = m(r, 1)*a(XY) + m(r, 2)*a(YY) + m(r, 3)*a(YZ)
      t(r, 3) = m(r, 1)*a(ZX) + m(r, 2)*a(YZ) + m(r, 3)*a(ZZ)
    end do
    c(XX) = factor*(t(1, 1)*m(1, 1) + t(1, 2)*m(1, 2) + t(1, 3)*m(1, 3))
    c(YY) = factor*(t(2, 1)*m(2, 1) + t(2, 2)*m(2, 2) + t(2, 3)*m(2, 3))
    c(ZZ) = factor*(t(3, 1)*m(3, 1) + t(3, 2)*m(3, 2) + t(3, 3)*m(3, 3))
    c(XY) = factor*(t(1, 1)*m(2, 1) + t(1, 2)*m(2, 2) + t(1, 3)*m(2, 3))
    c(YZ) = factor*(t(2, 1)*m(3, 1) + t(2, 2)*m(3, 2) + t(2, 3)*m(3, 3))
    c(ZX) = factor*(t(3, 1)*m(1, 1) + t(3, 2)*m(1, 2) + t(3, 3)*m(1, 3))
  end subroutine symmetric_sandwich

  !> a : a of a symmetric tensor given by its 6 components.
  pure real(wp) function sym_norm_squared(a)
    real(wp), intent(in) :: a(SYM)   !< XX YY ZZ XY YZ ZX
    sym_norm_squared = a(XX)*a(XX) + a(YY)*a(YY) + a(ZZ)*a(ZZ) + &
                       2.0_wp*(a(XY)*a(XY) + a(YZ)*a(YZ) + a(ZX)*a(ZX))
  end function sym_norm_squared

  !> Frobenius norm sqrt(a : a) of a symmetric tensor given by its 6 components.
  pure real(wp) function sym_norm(a)
    real(wp), intent(in) :: a(SYM)   !< XX YY ZZ XY YZ ZX
    sym_norm = sqrt(sym_norm_squared(a))
  end function sym_norm

  !> Determinant of a symmetric tensor given by its 6 components.
  pure real(wp) function sym_det(a)
    real(wp), intent(in) :: a(SYM)   !< XX YY ZZ XY YZ ZX
    sym_det = a(XX)*(a(YY)*a(ZZ) - a(YZ)*a(YZ)) - a(XY)*(a(XY)*a(ZZ) - a(YZ)*a(ZX)) &
            + a(ZX)*(a(XY)*a(YZ) - a(YY)*a(ZX))
  end function sym_det

  !> The full 3x3 matrix of a symmetric tensor given by its 6 components.
  pure subroutine sym_to_full(a, m)
    real(wp), intent(in) :: a(SYM)     !< XX YY ZZ XY YZ ZX
    real(wp), intent(out) :: m(3,3)    !< the matrix
    m(1,1) = a(XX)
    m(2,2) = a(YY)
    m(3,3) = a(ZZ)
    m(1,2) = a(XY)
    m(2,1) = a(XY)
    m(2,3) = a(YZ)
    m(3,2) = a(YZ)
    m(3,1) = a(ZX)
    m(1,3) = a(ZX)
  end subroutine sym_to_full

  !> Set a failed status with the material id.
  pure subroutine fail(status, mat, message)
    type(status_t), intent(inout) :: status   !< set to failed
    type(material_t), intent(in) :: mat       !< the material
    character(len=*), intent(in) :: message   !< what went wrong
    status%ok = .false.
    status%message = 'material '//itoa(mat%id)//': '//message
  end subroutine fail

end module mefem_mat_j2_plasticity
