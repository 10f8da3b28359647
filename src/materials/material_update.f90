!> The one dispatch site of the material family: material_update calls the law of the
!> material's kind. Every law is a pure, allocation-free point kernel with the same contract,
!> shared by the implicit (Newton) and explicit solvers:
!>
!> in:  the material card (mefem_model material_t), the model's curves (for *MAT_024 LCSS;
!>      pass model%curves, allocated, possibly of size 0), the new deformation gradient
!>      F_{n+1}, and the point's history at t_n (mefem_material_state: Cbar_p^-1, alpha_n);
!> out: the history at t_{n+1}, the Kirchhoff stress tau = J sigma (symmetric 3x3), the
!>      current dilatational wave speed (for the explicit stable step), a status, and when
!>      asked the spatial tangent c_tau(3,3,3,3) of the Lie derivative of tau:
!>      L_v tau = c : d, equivalently for dF = h F the directional derivative of tau is
!>      c : sym(h) + h tau + tau h^T. c has the minor symmetries c_ijkl = c_jikl = c_ijlk, so
!>      the element may contract it with unsymmetrised gradients:
!>      K_IJ(ik) = sum w [ a_j^I c_ijkl a_l^J + delta_ik a_j^I tau_jl a_l^J ]
!>      (formulation.md 2.7). It is major-symmetric for the hyperelastic laws, not in plastic
!>      steps of J2 (exact linearisation of the return map).
!> The update never writes hist_old: evaluating the same step again (Newton iterations, a cut
!> step) starts from the same converged history. A failing point (det F <= 0, return map not
!> converged, unsupported kind) returns status%ok = .false. with a message naming the material,
!> and zero stress; the driver adds the element and decides (cut the step or stop).
!>
!> Laws: *MAT_ELASTIC -> mefem_mat_elastic (compressible neo-Hookean); *MAT_024, *MAT_018,
!> *MAT_015 and *MAT_098 -> mefem_mat_j2_plasticity with the hardening law of mefem_hardening
!> (Johnson-Cook: the yield scale is the rate factor times the thermal factor 1 - T*^M of the
!> point's temperature at t_n, T* = (T - TR)/(TM - TR); after the update the temperature rises
!> by the plastic work K(alpha_{n+1}) dalpha/(rho CP), adiabatic: doc/theory.md 4); *MAT_003 -> its
!> mixed-hardening update (mat_j2_kinematic_update; explicit: point by point); *MAT_027 ->
!> mefem_mat_mooney_rivlin. *MAT_RIGID has no stress update (rigid bodies are moved as a
!> whole); asking for one is reported as a failure.
module mefem_material_update
  use mefem_kinds, only: wp
  use mefem_model, only: material_t, curve_t, EROSION_CRITERIA, EROSION_MXPRES, EROSION_MNEPS, &
                         EROSION_EFFEPS, EROSION_VOLEPS, EROSION_MNPRES, EROSION_SIGP1, &
                         EROSION_SIGVM, EROSION_MXEPS, EROSION_FAILTM, MAT_ELASTIC, MAT_PIECEWISE_LINEAR, MAT_POWER_LAW, &
                         MAT_PLASTIC_KINEMATIC, MAT_RIGID, MAT_MOONEY_RIVLIN, &
                         MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK, SPALL_NONE, &
                         SPALL_PRESSURE_CUTOFF, SPALL_PRINCIPAL, SPALL_HYDROSTATIC
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa
  use mefem_material_state, only: NHIST, BLOCK_POINTS, HIST_ALPHA, HIST_TEMPERATURE, &
                                  HIST_DAMAGE, HIST_SPALL, POINT_INTACT, POINT_SPALLED, &
                                  POINT_FAILED_KEPT
  use mefem_hardening, only: HARDENING_POWER_LAW, HARDENING_JOHNSON_COOK, HARDENING_LINEAR, &
                             piecewise_linear_law, hardening_rate_factor, rate_dependent, &
                             rate_table_material, HARDENING_CURVE, viscoplastic, &
                             hardening_yield
  use mefem_mat_elastic, only: mat_elastic_update, mat_elastic_update_block, lame_constants
  use mefem_mat_j2_plasticity, only: mat_j2_update, mat_j2_update_block, mat_j2_kinematic_update, &
                                     mat_j2_kinematic_update_block
  use mefem_mat_mooney_rivlin, only: mat_mooney_rivlin_update
  use mefem_tensor_algebra, only: symmetric_eigenvalues, determinant
  implicit none
  private

  public :: material_update, material_update_block, material_elastic_moduli, rate_dependent
  public :: material_fails, failed_point_energy, erosion_criteria_met, point_fails
  public :: johnson_cook_failure_strain, spall_active

  !> Intervals of Simpson's rule for the plastic work of a failed point
  integer, parameter :: PLASTIC_WORK_INTERVALS = 8

contains

  !> Update one material point to F_{n+1}: new history, Kirchhoff stress, wave speed and
  !> optionally the spatial tangent (contract in the module header).
  pure subroutine material_update(mat, curves, f_new, hist_old, hist_new, tau, c_tau, &
                                  sound_speed, status, strain_rate, committed, dt, spall)
    type(material_t), intent(in) :: mat                !< the material card
    type(curve_t), intent(in) :: curves(:)              !< the model's curves (LCSS)
    real(wp), intent(in) :: f_new(3,3)                  !< deformation gradient F_{n+1}
    real(wp), intent(in) :: hist_old(NHIST)             !< history at t_n
    real(wp), intent(out) :: hist_new(NHIST)            !< history at t_{n+1}
    real(wp), intent(out) :: tau(3,3)                   !< Kirchhoff stress
    real(wp), intent(out), optional :: c_tau(3,3,3,3)   !< spatial tangent of tau
    real(wp), intent(out) :: sound_speed                !< dilatational wave speed
    type(status_t), intent(out) :: status               !< failure and its reason
    real(wp), intent(in), optional :: strain_rate       !< effective strain rate (plasticity
                                                        !< with rate effects; 0 if absent)
    logical, intent(in), optional :: committed          !< hist_old already holds F (output):
                                                        !< the committed stress, no yield check
    real(wp), intent(in), optional :: dt                !< the step (VP = 1: the plastic rate
                                                        !< (alpha - alpha_n)/dt; 0 if absent)
    logical, intent(in), optional :: spall              !< apply *MAT_015's spall and kept
                                                        !< failure (spall_stress; the explicit
                                                        !< analysis); no if absent
    real(wp) :: factor, rate, voigt(6)
    logical :: output
    factor = 1.0_wp
    if (present(strain_rate)) factor = hardening_rate_factor(mat, curves, strain_rate)
    output = .false.
    if (present(committed)) output = committed
    select case (mat%kind)
    case (MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK)
      factor = factor*thermal_factor(mat, hist_old(HIST_TEMPERATURE))
      call mat_j2_update(mat, curves, HARDENING_JOHNSON_COOK, f_new, hist_old, hist_new, tau, &
                         sound_speed, status, c_tau, factor, committed)
      if (status%ok .and. .not. output) then
        call heat_from_plastic_work(mat, curves, factor, hist_old(HIST_ALPHA), &
                                    hist_new(HIST_ALPHA), hist_new(HIST_TEMPERATURE))
        rate = 0.0_wp
        if (present(strain_rate)) rate = strain_rate
        call accumulate_damage(mat, rate, hist_old(HIST_ALPHA), hist_new(HIST_ALPHA), &
            hist_new(HIST_TEMPERATURE), [tau(1,1), tau(2,2), tau(3,3), tau(1,2), tau(2,3), &
            tau(3,1)], hist_new(HIST_DAMAGE))
      end if
      if (present(spall)) then
        if (spall .and. status%ok .and. spall_active(mat)) then
          voigt = [tau(1,1), tau(2,2), tau(3,3), tau(1,2), tau(2,3), tau(3,1)]
          call spall_stress(mat, determinant(f_new), hist_old, hist_new, voigt)
          tau = reshape([voigt(1), voigt(4), voigt(6), voigt(4), voigt(2), voigt(5), voigt(6), &
                         voigt(5), voigt(3)], [3, 3])
        end if
      end if
    case (MAT_ELASTIC)
      call mat_elastic_update(mat, f_new, hist_old, hist_new, tau, sound_speed, status, c_tau)
    case (MAT_PIECEWISE_LINEAR)
      if (viscoplastic(mat) .and. .not. output .and. present(dt)) then
        ! VP = 1: the yield stress of the plastic strain rate of this step
        call mat_j2_update(viscoplastic_material(mat, hist_old(HIST_ALPHA), dt), curves, &
                           piecewise_linear_law(mat), f_new, hist_old, hist_new, tau, &
                           sound_speed, status, c_tau, factor, committed)
      else if (mat%lcss_table > 0) then         ! LCSS a table: the curves of the rate
        rate = 0.0_wp
        if (present(strain_rate)) rate = strain_rate
        call mat_j2_update(rate_table_material(mat, curves, rate), curves, HARDENING_CURVE, &
                           f_new, hist_old, hist_new, tau, sound_speed, status, c_tau, factor, &
                           committed)
      else
        call mat_j2_update(mat, curves, piecewise_linear_law(mat), f_new, hist_old, hist_new, &
                           tau, sound_speed, status, c_tau, factor, committed)
      end if
    case (MAT_POWER_LAW)
      if (viscoplastic(mat) .and. .not. output .and. present(dt)) then
        call mat_j2_update(viscoplastic_material(mat, hist_old(HIST_ALPHA), dt), curves, &
                           HARDENING_POWER_LAW, f_new, hist_old, hist_new, tau, sound_speed, &
                           status, c_tau, factor, committed)
      else
        call mat_j2_update(mat, curves, HARDENING_POWER_LAW, f_new, hist_old, hist_new, tau, &
                           sound_speed, status, c_tau, factor, committed)
      end if
    case (MAT_MOONEY_RIVLIN)
      call mat_mooney_rivlin_update(mat, f_new, hist_old, hist_new, tau, sound_speed, status, &
                                    c_tau)
    case (MAT_PLASTIC_KINEMATIC)
      if (viscoplastic(mat) .and. .not. output .and. present(dt)) then
        call mat_j2_kinematic_update(viscoplastic_material(mat, hist_old(HIST_ALPHA), dt), &
                                     f_new, hist_old, hist_new, tau, sound_speed, status, &
                                     c_tau, factor, committed)
      else
        call mat_j2_kinematic_update(mat, f_new, hist_old, hist_new, tau, sound_speed, status, &
                                     c_tau, factor, committed)
      end if
    case default
      hist_new = hist_old
      tau = 0.0_wp
      sound_speed = 0.0_wp
      if (present(c_tau)) c_tau = 0.0_wp
      status%ok = .false.
      if (mat%kind == MAT_RIGID) then
        status%message = 'material '//itoa(mat%id)//': *MAT_RIGID has no stress update'
      else
        status%message = 'material '//itoa(mat%id)//': unknown material kind '//itoa(mat%kind)
      end if
    end select
  end subroutine material_update

  !> Explicit update of a block of n points of one material (structure of arrays, entry i of
  !> every array is point i; no tangent, no wave speed): the J2 laws (*MAT_003 with BETA = 1
  !> too) and *MAT_ELASTIC by their block kernels, the other laws point by point through material_update (same results as
  !> material_update point by point). A point whose update fails gets ok(i) = .false. and keeps its history;
  !> material_update on it gives the reason.
  subroutine material_update_block(mat, curves, n, f, j, hist, tau, ok, strain_rate, dt)
    type(material_t), intent(in) :: mat                !< the material card
    type(curve_t), intent(in) :: curves(:)              !< the model's curves (LCSS)
    integer, intent(in) :: n                            !< points in the block (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS             !< leading dimension
    real(wp), intent(in) :: f(ld, 9)                    !< F_{n+1}, column by column
    real(wp), intent(in) :: j(ld)                       !< det F_{n+1}
    real(wp), intent(inout) :: hist(ld, NHIST)          !< histories t_n -> t_{n+1}
    real(wp), intent(out) :: tau(ld, 6)                 !< Kirchhoff stress XX YY ZZ XY YZ ZX
    logical, intent(out) :: ok(ld)                      !< point updated
    real(wp), intent(in), optional :: strain_rate(ld)   !< effective strain rates (0 if absent)
    real(wp), intent(in), optional :: dt                !< the step (VP = 1)
    real(wp) :: f_point(3, 3), tau_point(3, 3), hist_new(NHIST), sound, rate(ld), factor(ld)
    real(wp) :: alpha_old(ld), hist_old(ld, NHIST)
    type(status_t) :: status
    logical :: spalling
    integer :: i
    rate(1:n) = 0.0_wp
    if (present(strain_rate)) rate(1:n) = strain_rate(1:n)
    select case (mat%kind)
    case (MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK)
      do i = 1, n
        factor(i) = hardening_rate_factor(mat, curves, rate(i))* &
                    thermal_factor(mat, hist(i, HIST_TEMPERATURE))
        alpha_old(i) = hist(i, HIST_ALPHA)
      end do
      spalling = spall_active(mat)
      if (spalling) hist_old(1:n, :) = hist(1:n, :)
      call mat_j2_update_block(mat, curves, HARDENING_JOHNSON_COOK, n, f, j, hist, tau, ok, &
                               factor)
      do i = 1, n
        if (.not. ok(i)) cycle
        call heat_from_plastic_work(mat, curves, factor(i), alpha_old(i), hist(i, HIST_ALPHA), &
                                    hist(i, HIST_TEMPERATURE))
        call accumulate_damage(mat, rate(i), alpha_old(i), hist(i, HIST_ALPHA), &
                               hist(i, HIST_TEMPERATURE), tau(i, :), hist(i, HIST_DAMAGE))
        if (spalling) then
          hist_new = hist(i, :)
          call spall_stress(mat, j(i), hist_old(i, :), hist_new, tau(i, :))
          hist(i, :) = hist_new
        end if
      end do
    case (MAT_PIECEWISE_LINEAR, MAT_POWER_LAW)
      if (mat%lcss_table > 0 .or. viscoplastic(mat)) then   ! a law per point: one by one
        call points_one_by_one()
      else if (present(strain_rate)) then
        do i = 1, n
          factor(i) = hardening_rate_factor(mat, curves, rate(i))
        end do
        call mat_j2_update_block(mat, curves, block_law(mat), n, f, j, hist, tau, ok, factor)
      else
        call mat_j2_update_block(mat, curves, block_law(mat), n, f, j, hist, tau, ok)
      end if
    case (MAT_ELASTIC)
      call mat_elastic_update_block(mat, n, f, j, tau, ok)
    case (MAT_PLASTIC_KINEMATIC)
      ! BETA = 1 (no back stress) is *MAT_024's linear law (doc/theory.md 4): its block kernel
      if (mat%beta == 1.0_wp .and. .not. viscoplastic(mat)) then
        if (present(strain_rate)) then
          do i = 1, n
            factor(i) = hardening_rate_factor(mat, curves, rate(i))
          end do
          call mat_j2_update_block(mat, curves, HARDENING_LINEAR, n, f, j, hist, tau, ok, factor)
        else
          call mat_j2_update_block(mat, curves, HARDENING_LINEAR, n, f, j, hist, tau, ok)
        end if
      else if (.not. viscoplastic(mat)) then       ! kinematic hardening
        if (present(strain_rate)) then
          do i = 1, n
            factor(i) = hardening_rate_factor(mat, curves, rate(i))
          end do
          call mat_j2_kinematic_update_block(mat, n, f, j, hist, tau, ok, factor)
        else
          call mat_j2_kinematic_update_block(mat, n, f, j, hist, tau, ok)
        end if
      else
        call points_one_by_one()
      end if
    case default
      call points_one_by_one()
    end select

  contains

    !> The block's points one by one through material_update.
    subroutine points_one_by_one()
      do i = 1, n
        f_point = reshape(f(i, :), [3, 3])
        call material_update(mat, curves, f_point, hist(i, :), hist_new, tau_point, &
                             sound_speed=sound, status=status, strain_rate=rate(i), dt=dt)
        ok(i) = status%ok
        tau(i, :) = [tau_point(1, 1), tau_point(2, 2), tau_point(3, 3), tau_point(1, 2), &
                     tau_point(2, 3), tau_point(3, 1)]
        if (ok(i)) hist(i, :) = hist_new
      end do
    end subroutine points_one_by_one

  end subroutine material_update_block

  !> The material for one VP = 1 update: alpha_n and the step set (viscoplastic_scale).
  pure function viscoplastic_material(mat, alpha_old, dt) result(local)
    type(material_t), intent(in) :: mat                !< *MAT_024 with VP = 1
    real(wp), intent(in) :: alpha_old                  !< alpha_n
    real(wp), intent(in) :: dt                         !< the step (> 0 for the scale)
    type(material_t) :: local
    local = mat
    local%vp_alpha_old = alpha_old
    local%vp_dt = max(dt, 0.0_wp)
  end function viscoplastic_material

  !> The hardening law of a J2 material of the block kernel (*MAT_024's or the power law).
  pure integer function block_law(mat)
    type(material_t), intent(in) :: mat                !< *MAT_024 or *MAT_018
    block_law = HARDENING_POWER_LAW
    if (mat%kind == MAT_PIECEWISE_LINEAR) block_law = piecewise_linear_law(mat)
  end function block_law

  !> Small-strain Lame constants of a material (for the explicit stable time step):
  !> *MAT_ELASTIC and the J2 laws from E and PR; *MAT_MOONEY-RIVLIN_RUBBER mu = 2 (A + B) and
  !> lambda = kappa - 2 mu/3 with its bulk modulus kappa = 2 mu (1 + PR)/(3 (1 - 2 PR)), i.e.
  !> the Lame constants of E = 2 mu (1 + PR) and PR. Zero for *MAT_RIGID and unknown kinds.
  pure subroutine material_elastic_moduli(mat, lambda, mu)
    type(material_t), intent(in) :: mat     !< the material card
    real(wp), intent(out) :: lambda         !< Lame's first constant
    real(wp), intent(out) :: mu             !< shear modulus
    select case (mat%kind)
    case (MAT_ELASTIC, MAT_PIECEWISE_LINEAR, MAT_POWER_LAW, MAT_PLASTIC_KINEMATIC, &
          MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK)
      call lame_constants(mat%young, mat%poisson, lambda, mu)
    case (MAT_MOONEY_RIVLIN)
      call lame_constants(4.0_wp*(mat%mr_a + mat%mr_b)*(1.0_wp + mat%poisson), mat%poisson, &
                          lambda, mu)
    case default
      lambda = 0.0_wp
      mu = 0.0_wp
    end select
  end subroutine material_elastic_moduli

  !> A point of this material fails (the explicit analysis erodes it) when its equivalent
  !> plastic strain reaches the material's failure strain (FAIL, FS, EPSF, PSFAIL > 0).
  pure logical function material_fails(mat)
    type(material_t), intent(in) :: mat                !< the material card
    material_fails = mat%failure_strain > 0.0_wp .and. any(mat%kind == [MAT_PIECEWISE_LINEAR, &
        MAT_POWER_LAW, MAT_PLASTIC_KINEMATIC, MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK])
    material_fails = material_fails .or. mat%add_erosion .or. mat%jc_fails
  end function material_fails

  !> A point fails now (explicit: erosion): its equivalent plastic strain reached the failure
  !> strain, its Johnson-Cook damage reached 1 or its *MAT_ADD_EROSION criteria are met.
  pure logical function point_fails(mat, alpha, damage, f, tau, j, time)
    type(material_t), intent(in) :: mat                !< the material card
    real(wp), intent(in) :: alpha                      !< equivalent plastic strain (updated)
    real(wp), intent(in) :: damage                     !< HIST_DAMAGE (updated)
    real(wp), intent(in) :: f(9)                       !< F, column by column
    real(wp), intent(in) :: tau(6)                     !< Kirchhoff stress XX YY ZZ XY YZ ZX
    real(wp), intent(in) :: j                          !< J of the stress
    real(wp), intent(in) :: time                       !< the time of the state
    point_fails = .false.
    if (mat%failure_strain > 0.0_wp) point_fails = alpha >= mat%failure_strain
    if (.not. point_fails .and. mat%jc_fails .and. .not. mat%jc_keep_failed) &
      point_fails = damage >= 1.0_wp
    if (.not. point_fails .and. mat%add_erosion) point_fails = erosion_criteria_met(mat, f, &
                                                                   tau, j, time)
  end function point_fails

  !> The material limits its points' tension (*MAT_015 PC with SPALL) or keeps its failed
  !> points (EROD /= 0): spall_stress applies after its update (explicit analysis).
  pure logical function spall_active(mat)
    type(material_t), intent(in) :: mat                !< the material card
    spall_active = mat%kind == MAT_JOHNSON_COOK .and. (mat%spall /= SPALL_NONE .or. &
                                                       mat%jc_keep_failed)
  end function spall_active

  !> *MAT_015 spall and kept failure on a point's updated stress (Kirchhoff tau = J sigma,
  !> Voigt XX YY ZZ XY YZ ZX) and history, with p = -tr(sigma)/3 (positive in compression):
  !>  - SPALL 1 (pressure cutoff): p >= PC, the mean stress capped, nothing remembered;
  !>  - SPALL 2: the point spalls when its largest principal stress reaches -PC; SPALL 3: when
  !>    p < PC; a spalled point (HIST_SPALL = POINT_SPALLED) carries compression only:
  !>    sigma = -max(p, 0) I;
  !>  - EROD /= 0: a point whose Johnson-Cook damage reached 1 is kept, not eroded
  !>    (POINT_FAILED_KEPT): sigma = -p I (with SPALL 1's cutoff).
  !> A point marked before this step keeps its history of then (no more plastic strain,
  !> heating or damage: it has no deviatoric stress to do plastic work).
  pure subroutine spall_stress(mat, j, hist_old, hist_new, tau)
    type(material_t), intent(in) :: mat                !< *MAT_015
    real(wp), intent(in) :: j                          !< J of the stress
    real(wp), intent(in) :: hist_old(NHIST)            !< history at t_n
    real(wp), intent(inout) :: hist_new(NHIST)         !< history at t_{n+1}
    real(wp), intent(inout) :: tau(6)                  !< Kirchhoff stress (Voigt)
    real(wp) :: mean, pressure, principal(3)
    mean = (tau(1) + tau(2) + tau(3))/3.0_wp
    pressure = -mean/j
    if (hist_old(HIST_SPALL) /= POINT_INTACT) then
      hist_new = hist_old
    else
      select case (mat%spall)
      case (SPALL_PRINCIPAL)
        principal = symmetric_eigenvalues(tau/j)
        if (maxval(principal) >= -mat%pressure_cutoff) hist_new(HIST_SPALL) = POINT_SPALLED
      case (SPALL_HYDROSTATIC)
        if (pressure < mat%pressure_cutoff) hist_new(HIST_SPALL) = POINT_SPALLED
      end select
      if (hist_new(HIST_SPALL) == POINT_INTACT .and. mat%jc_keep_failed .and. &
          hist_new(HIST_DAMAGE) >= 1.0_wp) hist_new(HIST_SPALL) = POINT_FAILED_KEPT
    end if
    if (mat%spall == SPALL_PRESSURE_CUTOFF) pressure = max(pressure, mat%pressure_cutoff)
    if (hist_new(HIST_SPALL) == POINT_SPALLED) then
      tau = [-j*max(pressure, 0.0_wp)*[1.0_wp, 1.0_wp, 1.0_wp], 0.0_wp, 0.0_wp, 0.0_wp]
    else if (hist_new(HIST_SPALL) == POINT_FAILED_KEPT) then
      tau = [-j*pressure*[1.0_wp, 1.0_wp, 1.0_wp], 0.0_wp, 0.0_wp, 0.0_wp]
    else if (mat%spall == SPALL_PRESSURE_CUTOFF) then
      tau(1:3) = tau(1:3) - mean - j*pressure
    end if
  end subroutine spall_stress

  !> Johnson-Cook failure strain eps_f = max([D1 + D2 exp(D3 s*)][1 + D4 ln r*][1 + D5 T*],
  !> EFMIN) at the triaxiality s* = sigma_m/sigma_vm (mean stress, positive in tension, over
  !> the von Mises stress: Johnson and Cook 1985), the rate ratio r* = rate/EPSO (ln taken
  !> above 1, as the strength's rate term) and T* = (T - TR)/(TM - TR) (0 without TM > TR).
  pure real(wp) function johnson_cook_failure_strain(mat, triaxiality, rate, theta) &
      result(eps_f)
    type(material_t), intent(in) :: mat                !< *MAT_015 with jc_fails
    real(wp), intent(in) :: triaxiality                !< s*
    real(wp), intent(in) :: rate                       !< effective strain rate
    real(wp), intent(in) :: theta                      !< temperature rise T - TR
    real(wp) :: rate_term, thermal_term
    rate_term = 1.0_wp
    if (rate > mat%reference_rate) rate_term = 1.0_wp + &
        mat%jc_damage(4)*log(rate/mat%reference_rate)
    thermal_term = 1.0_wp
    if (mat%melt_temperature > mat%room_temperature) thermal_term = 1.0_wp + &
        mat%jc_damage(5)*max(theta, 0.0_wp)/(mat%melt_temperature - mat%room_temperature)
    eps_f = (mat%jc_damage(1) + mat%jc_damage(2)*exp(mat%jc_damage(3)*triaxiality))* &
            rate_term*thermal_term
    eps_f = max(eps_f, mat%jc_min_failure_strain)
  end function johnson_cook_failure_strain

  !> Johnson-Cook damage (*MAT_015 with D1 or D2): D += (alpha_new - alpha_old)/eps_f at the
  !> step's end stress, rate and temperature.
  pure subroutine accumulate_damage(mat, rate, alpha_old, alpha_new, theta, tau, damage)
    type(material_t), intent(in) :: mat                !< the material card
    real(wp), intent(in) :: rate                       !< effective strain rate
    real(wp), intent(in) :: alpha_old, alpha_new       !< plastic strain before and after
    real(wp), intent(in) :: theta                      !< temperature rise (updated)
    real(wp), intent(in) :: tau(6)                     !< Kirchhoff stress XX YY ZZ XY YZ ZX
    real(wp), intent(inout) :: damage                  !< the damage sum
    real(wp) :: mean, von_mises
    if (.not. mat%jc_fails .or. .not. alpha_new > alpha_old) return
    mean = (tau(1) + tau(2) + tau(3))/3.0_wp
    von_mises = sqrt(1.5_wp*((tau(1) - mean)**2 + (tau(2) - mean)**2 + (tau(3) - mean)**2 + &
                             2.0_wp*(tau(4)**2 + tau(5)**2 + tau(6)**2)))
    if (.not. von_mises > 0.0_wp) return
    damage = damage + (alpha_new - alpha_old)/ &
             johnson_cook_failure_strain(mat, mean/von_mises, rate, theta)
  end subroutine accumulate_damage

  !> *MAT_ADD_EROSION: at least NCS of the material's criteria met at a point, from its Cauchy
  !> stress sigma = tau/J (pressure p = -tr(sigma)/3, positive in compression; equivalent
  !> stress sqrt(3/2 s:s); principal stresses), its logarithmic strain (principal values
  !> ln(lambda_i)/2 of the eigenvalues of F F^T, volumetric ln J, effective sqrt(2/3 e:e) of
  !> the deviator e) and the time.
  pure logical function erosion_criteria_met(mat, f, tau, j, time) result(met)
    type(material_t), intent(in) :: mat                !< the material card (add_erosion)
    real(wp), intent(in) :: f(9)                       !< F, column by column
    real(wp), intent(in) :: tau(6)                     !< Kirchhoff stress XX YY ZZ XY YZ ZX
    real(wp), intent(in) :: j                          !< J of the stress (> 0)
    real(wp), intent(in) :: time                       !< the time of the state
    real(wp) :: sigma(6), pressure, dev(6), b(6), stress_principal(3), strain_principal(3)
    real(wp) :: strain_dev(3), value(EROSION_CRITERIA)
    logical :: hit(EROSION_CRITERIA)
    met = .false.
    if (.not. mat%add_erosion .or. .not. j > 0.0_wp) return
    sigma = tau/j
    pressure = -(sigma(1) + sigma(2) + sigma(3))/3.0_wp
    dev = sigma
    dev(1:3) = dev(1:3) + pressure
    stress_principal = symmetric_eigenvalues(sigma)
    ! B = F F^T (F(r, c) = f(r + 3 (c - 1)))
    b(1) = f(1)**2 + f(4)**2 + f(7)**2
    b(2) = f(2)**2 + f(5)**2 + f(8)**2
    b(3) = f(3)**2 + f(6)**2 + f(9)**2
    b(4) = f(1)*f(2) + f(4)*f(5) + f(7)*f(8)
    b(5) = f(2)*f(3) + f(5)*f(6) + f(8)*f(9)
    b(6) = f(1)*f(3) + f(4)*f(6) + f(7)*f(9)
    strain_principal = 0.5_wp*log(max(symmetric_eigenvalues(b), tiny(1.0_wp)))
    strain_dev = strain_principal - sum(strain_principal)/3.0_wp
    value = [pressure, strain_principal(3), sqrt(2.0_wp/3.0_wp*sum(strain_dev**2)), &
             sum(strain_principal), pressure, stress_principal(1), &
             sqrt(1.5_wp*(sum(dev(1:3)**2) + 2.0_wp*sum(dev(4:6)**2))), strain_principal(1), &
             time]
    associate (limit => mat%erosion_limit)
      hit = [value(EROSION_MXPRES) > limit(EROSION_MXPRES), &
             value(EROSION_MNEPS) < limit(EROSION_MNEPS), &
             value(EROSION_EFFEPS) > limit(EROSION_EFFEPS), &
             merge(value(EROSION_VOLEPS) > limit(EROSION_VOLEPS), &
                   value(EROSION_VOLEPS) < limit(EROSION_VOLEPS), &
                   limit(EROSION_VOLEPS) >= 0.0_wp), &
             value(EROSION_MNPRES) < limit(EROSION_MNPRES), &
             value(EROSION_SIGP1) > limit(EROSION_SIGP1), &
             value(EROSION_SIGVM) > limit(EROSION_SIGVM), &
             value(EROSION_MXEPS) > limit(EROSION_MXEPS), &
             value(EROSION_FAILTM) > limit(EROSION_FAILTM)]
    end associate
    met = count(hit .and. mat%erosion_used) >= mat%erosion_conditions
  end function erosion_criteria_met

  !> Internal energy per reference volume of a point that failed at the equivalent plastic
  !> strain alpha (glstat's eroded internal energy): the plastic work of the static hardening
  !> curve, int_0^alpha K(a) da by Simpson's rule (an estimate: rate and thermal factors that
  !> raised the flow stress are not counted, nor the elastic energy at failure, for metals a
  !> fraction of a percent of the plastic work).
  pure real(wp) function failed_point_energy(mat, curves, alpha) result(energy)
    type(material_t), intent(in) :: mat                !< the material card
    type(curve_t), intent(in) :: curves(:)             !< the model's curves (LCSS)
    real(wp), intent(in) :: alpha                      !< equivalent plastic strain (>= 0)
    real(wp) :: work, a, yield_stress, slope
    integer :: law, k
    select case (mat%kind)
    case (MAT_PIECEWISE_LINEAR)
      law = piecewise_linear_law(mat)
    case (MAT_POWER_LAW)
      law = HARDENING_POWER_LAW
    case (MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK)
      law = HARDENING_JOHNSON_COOK
    case default                                   ! *MAT_003: SIGY + ETAN-based modulus
      law = HARDENING_LINEAR
    end select
    work = 0.0_wp
    do k = 0, PLASTIC_WORK_INTERVALS                ! Simpson: 1 4 2 4 ... 2 4 1
      a = alpha*real(k, wp)/real(PLASTIC_WORK_INTERVALS, wp)
      call hardening_yield(law, mat, curves, a, yield_stress, slope)
      if (k == 0 .or. k == PLASTIC_WORK_INTERVALS) then
        work = work + yield_stress
      else
        work = work + merge(4.0_wp, 2.0_wp, mod(k, 2) == 1)*yield_stress
      end if
    end do
    energy = work*alpha/(3.0_wp*real(PLASTIC_WORK_INTERVALS, wp))
  end function failed_point_energy

  !> Johnson-Cook thermal softening 1 - T*^M at the temperature rise theta = T - TR,
  !> T* = theta/(TM - TR) (*MAT_015 with TM > TR; else 1); a molten point (T* >= 1) keeps
  !> epsilon x its cold yield stress (no deviatoric strength, to round-off).
  pure real(wp) function thermal_factor(mat, theta)
    type(material_t), intent(in) :: mat                !< the material card
    real(wp), intent(in) :: theta                      !< temperature rise
    real(wp) :: homologous
    thermal_factor = 1.0_wp
    if (mat%kind /= MAT_JOHNSON_COOK .or. .not. mat%melt_temperature > mat%room_temperature) &
      return
    homologous = theta/(mat%melt_temperature - mat%room_temperature)
    if (homologous <= 0.0_wp) return
    thermal_factor = max(1.0_wp - homologous**mat%jc_m, epsilon(1.0_wp))
  end function thermal_factor

  !> Adiabatic heating of a Johnson-Cook point (*MAT_015 with CP > 0): theta += (factor
  !> K(alpha_new)) (alpha_new - alpha_old)/(rho CP), the plastic work of the step per unit
  !> reference volume (the yield surface holds the Kirchhoff stress) at the step's end yield
  !> stress.
  pure subroutine heat_from_plastic_work(mat, curves, factor, alpha_old, alpha_new, theta)
    type(material_t), intent(in) :: mat                !< the material card
    type(curve_t), intent(in) :: curves(:)              !< the model's curves
    real(wp), intent(in) :: factor                     !< the step's yield scale
    real(wp), intent(in) :: alpha_old, alpha_new       !< plastic strain before and after
    real(wp), intent(inout) :: theta                   !< temperature rise
    real(wp) :: yield_stress, slope
    if (mat%kind /= MAT_JOHNSON_COOK .or. .not. mat%heat_capacity > 0.0_wp) return
    if (.not. alpha_new > alpha_old) return
    call hardening_yield(HARDENING_JOHNSON_COOK, mat, curves, alpha_new, yield_stress, slope)
    theta = theta + factor*yield_stress*(alpha_new - alpha_old)/(mat%density*mat%heat_capacity)
  end subroutine heat_from_plastic_work

end module mefem_material_update
