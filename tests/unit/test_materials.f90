!> Material library (src/materials): point kernels driven along deformation paths.
!> 1 uniaxial tension/compression of J2 (linear and power-law hardening) against the
!>   hardening curve and Hooke's law; 2 simple shear (J2 on the yield surface, neo-Hookean
!>   shear stress mu gamma); 3 objectivity under superposed (time-varying) rotations;
!> 4 plastic incompressibility (det be_bar = 1); 5 consistent tangents against central
!>   differences of tau(F) with the Lie-derivative identity; 6 det F <= 0 reported;
!> 7 hardening laws (values, slopes, LS-DYNA *MAT_018 strain offset, the seed-law identity);
!> 8 the block form of the hardening laws gives the point form's bits; 9 principal values of
!>   rotated diagonal tensors and the *MAT_ADD_EROSION criteria on rotated states;
!> 10 Johnson-Cook damage along a heated uniaxial path at a fixed rate against its integral;
!> 11 *MAT_024 VP = 1: the yield stress of the step's plastic strain rate.
program test_materials
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_errors, only: status_t
  use mefem_strings, only: rtoa, itoa
  use mefem_model, only: material_t, curve_t, MAT_ELASTIC, MAT_PIECEWISE_LINEAR, MAT_POWER_LAW, &
                         MAT_MOONEY_RIVLIN, MAT_RIGID, MAT_PLASTIC_KINEMATIC, &
                         EROSION_MXPRES, EROSION_MNEPS, &
                         EROSION_EFFEPS, EROSION_VOLEPS, EROSION_MNPRES, EROSION_SIGP1, &
                         EROSION_SIGVM, EROSION_MXEPS, EROSION_FAILTM, SPALL_PRESSURE_CUTOFF, &
                         SPALL_PRINCIPAL, SPALL_HYDROSTATIC
  use mefem_material_state, only: NHIST, HIST_ALPHA, HIST_DAMAGE, HIST_SPALL, POINT_SPALLED, &
                                  POINT_FAILED_KEPT, POINT_INTACT, material_state_init, &
                                  state_elastic_strain, state_plastic_metric
  use mefem_material_update, only: material_update, erosion_criteria_met, point_fails
  use mefem_hardening, only: hardening_yield, hardening_yield_block, piecewise_linear_law, power_law_strain_offset, &
                             plastic_modulus, HARDENING_POWER_LAW, HARDENING_LINEAR, &
                             HARDENING_TABLE, HARDENING_CURVE
  use mefem_tensor_algebra, only: IDENTITY, determinant, deviator, frobenius_norm, &
                                  symmetric_eigenvalues
  use mefem_test_fixtures, only: linear_steel, power_law_steel, table_steel, curve_steel, &
                                 elastic_steel, rubber, johnson_cook_steel
  implicit none

  type(curve_t), allocatable :: curves(:)

  call test_start('materials')
  call make_curves()
  call test_hardening()
  call test_hardening_block()
  call test_uniaxial(linear_steel(), 'linear hardening', 1.3_wp)
  call test_uniaxial(linear_steel(), 'linear hardening', 1.0_wp/1.3_wp)
  call test_uniaxial(power_law_steel(), 'power law', 1.3_wp)
  call test_uniaxial(power_law_steel(), 'power law', 1.0_wp/1.3_wp)
  call test_small_strain_hooke()
  call test_simple_shear()
  call test_objectivity()
  call test_tangents()
  call test_failures()
  call test_erosion_criteria()
  call test_johnson_cook_damage()
  call test_johnson_cook_spall()
  call test_viscoplastic()
  call test_finish()

contains

  ! ---------------------------------------------------------------- materials and helpers

  !> Curve 1: yield stress vs plastic strain for LCSS.
  subroutine make_curves()
    allocate(curves(1))
    curves(1)%id = 11
    curves(1)%n = 4
    curves(1)%t = [0.0_wp, 0.02_wp, 0.1_wp, 0.4_wp]
    curves(1)%f = [250.0_wp, 280.0_wp, 320.0_wp, 360.0_wp]
  end subroutine make_curves

  !> Von Mises value sqrt(3/2) |dev a|.
  real(wp) function von_mises(a)
    real(wp), intent(in) :: a(3,3)
    von_mises = sqrt(1.5_wp)*frobenius_norm(deviator(a))
  end function von_mises

  !> Yield stress of a J2 material at alpha.
  real(wp) function yield_of(mat, alpha)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: alpha
    real(wp) :: slope
    integer :: law
    if (mat%kind == MAT_POWER_LAW) then
      law = HARDENING_POWER_LAW
    else
      law = piecewise_linear_law(mat)
    end if
    call hardening_yield(law, mat, curves, alpha, yield_of, slope)
  end function yield_of

  !> Rotation by angle about axis (Rodrigues).
  function rotation(axis, angle) result(q)
    real(wp), intent(in) :: axis(3), angle
    real(wp) :: q(3,3), e(3), w(3,3)
    e = axis/norm2(axis)
    w = reshape([0.0_wp, e(3), -e(2), -e(3), 0.0_wp, e(1), e(2), -e(1), 0.0_wp], [3, 3])
    q = IDENTITY + sin(angle)*w + (1.0_wp - cos(angle))*matmul(w, w)
  end function rotation

  !> F = diag(stretch, lateral, lateral) with lateral solved (Newton, central-difference
  !> slope) for |tau_22| <= tolerance from hist_old; returns the update at the solution.
  subroutine uniaxial_step(mat, stretch, lateral, hist_old, hist_new, tau, tolerance, ok, rate, &
                           dt)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: stretch, tolerance
    real(wp), intent(inout) :: lateral
    real(wp), intent(in) :: hist_old(NHIST)
    real(wp), intent(out) :: hist_new(NHIST), tau(3,3)
    logical, intent(out) :: ok
    real(wp), intent(in), optional :: rate      !< effective strain rate given to the law
    real(wp), intent(in), optional :: dt        !< the step (VP = 1)
    real(wp) :: plus, minus, h, tau_h(3,3), hist_h(NHIST)
    integer :: iteration
    ok = .false.
    do iteration = 1, 50
      call update_diagonal(mat, stretch, lateral, hist_old, tau, hist_new, rate, dt)
      if (abs(tau(2,2)) <= tolerance) then
        ok = .true.
        return
      end if
      h = 1.0e-7_wp*lateral
      call update_diagonal(mat, stretch, lateral + h, hist_old, tau_h, hist_h, rate, dt)
      plus = tau_h(2,2)
      call update_diagonal(mat, stretch, lateral - h, hist_old, tau_h, hist_h, rate, dt)
      minus = tau_h(2,2)
      lateral = lateral - tau(2,2)*2.0_wp*h/(plus - minus)
    end do
  end subroutine uniaxial_step

  !> Update at F = diag(stretch, lateral, lateral) from hist_old.
  subroutine update_diagonal(mat, stretch, lateral, hist_old, tau, hist_new, rate, dt)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: stretch, lateral, hist_old(NHIST)
    real(wp), intent(out) :: tau(3,3), hist_new(NHIST)
    real(wp), intent(in), optional :: rate      !< effective strain rate given to the law
    real(wp), intent(in), optional :: dt        !< the step (VP = 1)
    real(wp) :: f(3,3), speed
    type(status_t) :: status
    f = 0.0_wp
    f(1,1) = stretch
    f(2,2) = lateral
    f(3,3) = lateral
    call material_update(mat, curves, f, hist_old, hist_new, tau, sound_speed=speed, &
                         status=status, strain_rate=rate, dt=dt)
  end subroutine update_diagonal

  ! ---------------------------------------------------------------- 7 hardening

  !> Values and slopes of every hardening law, the *MAT_018 strain offset rules and the
  !> seed-paper identity.
  subroutine test_hardening()
    type(material_t) :: mat
    real(wp) :: k, slope, kp, km, h, alpha, worst, eps_yp, sigma0, a, b
    real(wp), parameter :: ALPHAS(5) = [0.0013_wp, 0.013_wp, 0.07_wp, 0.31_wp, 0.9_wp]
    integer :: i, law, i_alpha
    character(len=24) :: name
    ! K' against central differences for all laws, away from table/curve points:
    ! the power law has K'' ~ K N(1-N)/eps^2: h = 1e-6 alpha gives truncation ~1e-12
    ! relative; table and curve are linear between points (round-off only)
    do law = 1, 5
      select case (law)
      case (1)
        mat = power_law_steel()
        name = 'power law SIGY>=0.02'
      case (2)
        mat = power_law_steel()
        mat%yield_stress = 0.0_wp
        name = 'power law SIGY=0'
      case (3)
        mat = linear_steel()
        name = 'linear'
      case (4)
        mat = table_steel()
        name = 'EPS/ES table'
      case (5)
        mat = curve_steel()
        name = 'LCSS curve'
      end select
      worst = 0.0_wp
      do i = 1, size(ALPHAS)
        alpha = ALPHAS(i)
        h = 1.0e-6_wp*alpha
        k = yield_of(mat, alpha)
        call slope_of(mat, alpha, slope)
        kp = yield_of(mat, alpha + h)
        km = yield_of(mat, alpha - h)
        worst = max(worst, abs((kp - km)/(2.0_wp*h) - slope)/max(abs(slope), 1.0_wp))
      end do
      call check(worst < 1.0e-6_wp, trim(name)//': K'' matches central differences', &
                 'worst relative error '//rtoa(worst))
    end do
    ! law selection of *MAT_024 (LCSS before table before SIGY/ETAN)
    call check(piecewise_linear_law(linear_steel()) == HARDENING_LINEAR .and. &
               piecewise_linear_law(table_steel()) == HARDENING_TABLE .and. &
               piecewise_linear_law(curve_steel()) == HARDENING_CURVE, &
               '*MAT_024 law: LCSS, then EPS/ES, then SIGY/ETAN')
    ! linear: Ep = E ETAN/(E - ETAN) exactly
    mat = linear_steel()
    call check_close(plastic_modulus(mat), 210000.0_wp*2000.0_wp/208000.0_wp, 1.0e-15_wp, &
                     'linear: plastic modulus E ETAN/(E - ETAN)')
    call check_close(yield_of(mat, 0.1_wp), 250.0_wp + 0.1_wp*plastic_modulus(mat), 1.0e-15_wp, &
                     'linear: K(0.1) = SIGY + 0.1 Ep')
    ! table: the points, and the last slope beyond the last point
    mat = table_steel()
    worst = 0.0_wp
    do i = 1, 4
      worst = max(worst, abs(yield_of(mat, mat%eps(i)) - mat%es(i)))
    end do
    call check(worst < 1.0e-12_wp, 'table: K(EPS_i) = ES_i')
    call check_close(yield_of(mat, 0.8_wp), 380.0_wp + 0.3_wp*30.0_wp/0.3_wp, 1.0e-14_wp, &
                     'table: linear extrapolation with the last slope')
    call slope_of(mat, 0.05_wp, slope)
    call check_close(slope, 50.0_wp/0.15_wp, 1.0e-13_wp, 'table: slope at a point is the '// &
                     'slope of the segment to the right')
    ! curve: values at points and extrapolation
    mat = curve_steel()
    call check_close(yield_of(mat, 0.1_wp), 320.0_wp, 1.0e-15_wp, 'LCSS: value at a point')
    call check_close(yield_of(mat, 0.7_wp), 360.0_wp + 0.3_wp*40.0_wp/0.3_wp, 1.0e-14_wp, &
                     'LCSS: linear extrapolation with the last slope')
    ! *MAT_018 strain offset
    mat = power_law_steel()
    call check_close(yield_of(mat, 0.0_wp), 250.0_wp, 1.0e-14_wp, &
                     'power law, SIGY >= 0.02: K(0) = SIGY')
    mat%yield_stress = 0.0_wp
    eps_yp = power_law_strain_offset(mat)
    call check_close(eps_yp, (210000.0_wp/530.0_wp)**(1.0_wp/(0.26_wp - 1.0_wp)), 1.0e-14_wp, &
                     'power law, SIGY = 0: eps_yp = (E/K)^(1/(N-1))')
    call check_close(yield_of(mat, 0.0_wp), 210000.0_wp*eps_yp, 1.0e-13_wp, &
                     'power law, SIGY = 0: initial yield on the elastic line (K(0) = E eps_yp)')
    mat%yield_stress = 0.004_wp
    call check_close(power_law_strain_offset(mat), 0.004_wp, 1.0e-15_wp, &
                     'power law, 0 < SIGY < 0.02: eps_yp = SIGY')
    ! seed law sigma_y0 (1 + a alpha)^b = *MAT_018 with K = sigma_y0 a^b, N = b, SIGY = sigma_y0
    do i = 1, 2
      if (i == 1) then
        sigma0 = 20.0_wp
        a = 1.0_wp
        b = 1.1_wp
      else
        sigma0 = 137.0_wp
        a = 2.5_wp
        b = 0.3_wp
      end if
      mat = power_law_steel()
      mat%k_strength = sigma0*a**b
      mat%n_exponent = b
      mat%yield_stress = sigma0
      call check_close(power_law_strain_offset(mat), 1.0_wp/a, 1.0e-14_wp, &
                       'seed law '//rtoa(a)//', '//rtoa(b)//': eps_yp = 1/a')
      worst = 0.0_wp
      do i_alpha = 0, 20
        alpha = 0.05_wp*i_alpha
        worst = max(worst, abs(yield_of(mat, alpha)/(sigma0*(1.0_wp + a*alpha)**b) - 1.0_wp))
      end do
      call check(worst < 1.0e-13_wp, 'seed law '//rtoa(a)//', '//rtoa(b)//': K(alpha) = '// &
                 'sigma_y0 (1 + a alpha)^b on [0, 1]', 'worst '//rtoa(worst))
    end do
    ! formulation.md 3: sigma_y(0, 0.1, 0.5, 1.0) = 20.0, 22.2, 31.2, 42.9 MPa (3 digits)
    mat = power_law_steel()
    mat%k_strength = 20.0_wp
    mat%n_exponent = 1.1_wp
    mat%yield_stress = 20.0_wp
    call check_close([yield_of(mat, 0.0_wp), yield_of(mat, 0.1_wp), yield_of(mat, 0.5_wp), &
                      yield_of(mat, 1.0_wp)], [20.0_wp, 22.2_wp, 31.2_wp, 42.9_wp], 0.0_wp, &
                     'seed punch law against the reference values (rounded to 0.05)', &
                     atol=0.05_wp)
  end subroutine test_hardening

  ! ---------------------------------------------------------------- 8 block hardening

  !> hardening_yield_block against hardening_yield, bit for bit, for every law: at 0, at each
  !> table / curve point and just below and above it, between points, past the last point
  !> (extrapolation) and at pseudo-random strains; a curve of 20 points (longer than the
  !> counted search takes) and a table of 8 points as well.
  subroutine test_hardening_block()
    integer, parameter :: N = 64
    type(material_t) :: mats(6)
    type(curve_t), allocatable :: long_curves(:)
    real(wp) :: alpha(N), k_block(N), slope_block(N), k_point, slope_point, r
    integer :: m, i, law, mismatches
    character(len=24), parameter :: names(6) = [character(len=24) :: 'linear', 'power law', &
        'table of 4', 'curve of 4', 'curve of 20', 'table of 8']
    allocate(long_curves(2))
    long_curves(1) = curves(1)
    long_curves(2)%id = 12
    long_curves(2)%n = 20
    long_curves(2)%t = [(0.01_wp*real(i - 1, wp)**1.5_wp, i = 1, 20)]
    long_curves(2)%f = [(250.0_wp + 40.0_wp*sqrt(long_curves(2)%t(i)), i = 1, 20)]
    mats(1) = linear_steel()
    mats(2) = power_law_steel()
    mats(3) = table_steel()
    mats(4) = curve_steel()
    mats(5) = curve_steel()
    mats(5)%lcss_curve = 2
    mats(6) = table_steel()
    mats(6)%n_points = 8
    mats(6)%eps = [0.0_wp, 0.01_wp, 0.03_wp, 0.06_wp, 0.1_wp, 0.2_wp, 0.4_wp, 0.8_wp]
    mats(6)%es = [200.0_wp, 230.0_wp, 255.0_wp, 275.0_wp, 290.0_wp, 310.0_wp, 330.0_wp, 345.0_wp]
    do m = 1, size(mats)
      alpha = 0.0_wp
      do i = 1, 8                          ! the table's / curve's points and their neighbours
        alpha(i) = mats(6)%eps(i)
        alpha(8 + i) = nearest(mats(6)%eps(i), -1.0_wp)
        alpha(16 + i) = nearest(mats(6)%eps(i), 1.0_wp)
      end do
      alpha(25:28) = curves(1)%t
      alpha(29:32) = mats(3)%eps(1:4)
      alpha(33:40) = long_curves(2)%t(13:20)
      alpha(41:44) = [1.0_wp, 2.5_wp, 0.0_wp, 1.0e-9_wp]          ! past the last points
      do i = 45, N
        call random_number(r)
        alpha(i) = 0.9_wp*r
      end do
      alpha = max(alpha, 0.0_wp)
      if (mats(m)%kind == MAT_POWER_LAW) then
        law = HARDENING_POWER_LAW
      else
        law = piecewise_linear_law(mats(m))
      end if
      call hardening_yield_block(law, mats(m), long_curves, N, alpha, k_block, slope_block)
      mismatches = 0
      do i = 1, N
        call hardening_yield(law, mats(m), long_curves, alpha(i), k_point, slope_point)
        if (k_block(i) /= k_point .or. slope_block(i) /= slope_point) mismatches = mismatches + 1
      end do
      call check(mismatches == 0, 'block hardening, '//trim(names(m))//': K and K'' as the '// &
                 'point form, bit for bit, at 64 strains', 'mismatches: '//itoa(mismatches))
    end do
  end subroutine test_hardening_block

  !> K'(alpha) of a J2 material.
  subroutine slope_of(mat, alpha, slope)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: alpha
    real(wp), intent(out) :: slope
    real(wp) :: k
    integer :: law
    if (mat%kind == MAT_POWER_LAW) then
      law = HARDENING_POWER_LAW
    else
      law = piecewise_linear_law(mat)
    end if
    call hardening_yield(law, mat, curves, alpha, k, slope)
  end subroutine slope_of

  ! ---------------------------------------------------------------- 1, 4 uniaxial

  !> Uniaxial stress path F = diag(s, l, l), s from 1 to final_stretch in 120 steps, lateral
  !> stretch l solved for tau_22 = 0. Once plastic: von Mises of tau = K(alpha) (return map),
  !> true stress against the hardening curve at the logarithmic plastic strain, alpha
  !> against that strain; det be_bar = 1 all along; volume change only elastic.
  subroutine test_uniaxial(mat, name, final_stretch)
    type(material_t), intent(in) :: mat
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: final_stretch
    real(wp) :: hist_old(NHIST), hist_new(NHIST), tau(3,3), be(3,3), f(3,3)
    real(wp) :: stretch, lateral, j, kappa, mu, alpha, log_plastic, sigma, k_alpha
    real(wp) :: worst_yield, worst_curve, worst_alpha, worst_det, worst_volume, worst_lateral
    integer :: step, n_plastic
    logical :: ok, all_ok
    character(len=64) :: tag
    integer, parameter :: STEPS = 120
    tag = trim(name)//merge(' tension    ', ' compression', final_stretch > 1.0_wp)
    kappa = mat%young/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
    mu = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
    call material_state_init(hist_old)
    lateral = 1.0_wp
    worst_yield = 0.0_wp
    worst_curve = 0.0_wp
    worst_alpha = 0.0_wp
    worst_det = 0.0_wp
    worst_volume = 0.0_wp
    worst_lateral = 0.0_wp
    n_plastic = 0
    all_ok = .true.
    do step = 1, STEPS
      stretch = final_stretch**(real(step, wp)/STEPS)
      call uniaxial_step(mat, stretch, lateral, hist_old, hist_new, tau, &
                         1.0e-11_wp*mat%yield_stress, ok)
      all_ok = all_ok .and. ok
      hist_old = hist_new
      worst_lateral = max(worst_lateral, abs(tau(2,2)) + abs(tau(3,3)))
      f = 0.0_wp
      f(1,1) = stretch
      f(2,2) = lateral
      f(3,3) = lateral
      call state_elastic_strain(hist_new, f, be)
      worst_det = max(worst_det, abs(determinant(be) - 1.0_wp))
      j = determinant(f)
      ! J from the elastic bulk law alone: tr(tau)/3 = kappa/2 (J^2 - 1)
      worst_volume = max(worst_volume, abs(j - sqrt(1.0_wp + 2.0_wp*(tau(1,1)/3.0_wp)/kappa)))
      alpha = hist_new(HIST_ALPHA)
      if (alpha <= 0.0_wp) cycle
      n_plastic = n_plastic + 1
      k_alpha = yield_of(mat, alpha)
      worst_yield = max(worst_yield, abs(von_mises(tau) - k_alpha)/k_alpha)
      ! logarithmic plastic strain: ln(stretch) - ln(elastic stretch), b_e = J^(2/3) be_bar
      log_plastic = abs(log(stretch) - 0.5_wp*log(j**(2.0_wp/3.0_wp)*be(1,1)))
      sigma = abs(tau(1,1))/j
      if (log_plastic > 0.01_wp) then
        worst_alpha = max(worst_alpha, abs(alpha - log_plastic)/log_plastic)
        worst_curve = max(worst_curve, abs(sigma - yield_of(mat, log_plastic))/sigma)
      end if
    end do
    call check(all_ok .and. worst_lateral < 1.0e-9_wp, trim(tag)//': lateral stress solved '// &
               'to zero')
    call check(n_plastic > 100, trim(tag)//': path is plastic ('//rtoa(real(n_plastic, wp))// &
               ' of 120 steps)')
    ! return-map tolerance 1e-13 plus the lateral residual 1e-11 SIGY
    call check(worst_yield < 1.0e-10_wp, trim(tag)//': von Mises of tau = K(alpha)', &
               'worst '//rtoa(worst_yield))
    ! alpha vs the logarithmic plastic strain: Simo's update moves be_bar by -2 I_bar dgamma n
    ! (not by the exponential map), so the axial log plastic strain grows at the rate
    ! alpha' I_bar/be_bar_11 = alpha' (1 -+ 2/3 sigma/mu): a model difference of 2/3 sigma/mu
    ! (~2e-3 here) plus a first-order step error (~1e-3 with 120 steps); tolerance 2 sigma/mu
    call check(worst_alpha < 2.0_wp*yield_of(mat, hist_old(HIST_ALPHA))/mu, trim(tag)// &
               ': alpha = logarithmic plastic strain to O(sigma/mu)', 'worst '//rtoa(worst_alpha))
    ! sigma = tau/J differs from K(alpha) by |J - 1| < 1.5e-3 (elastic volume change) and
    ! K(eps_p) from K(alpha) by K' |alpha - eps_p| (< 1e-3 relative here): tolerance 3e-3
    call check(worst_curve < 3.0e-3_wp, trim(tag)//': true stress = hardening curve at the '// &
               'logarithmic plastic strain', 'worst '//rtoa(worst_curve))
    ! 4: plastic incompressibility, det be_bar = 1 enforced to round-off
    call check(worst_det < 1.0e-12_wp, trim(tag)//': det be_bar = 1', 'worst '//rtoa(worst_det))
    call check(worst_volume < 1.0e-12_wp, trim(tag)//': J from the elastic bulk response only', &
               'worst '//rtoa(worst_volume))
  end subroutine test_uniaxial

  !> Elastic part of the uniaxial path at strain 1e-6: sigma = E eps, lateral strain = -nu eps
  !> (Hooke) to 1e-5 (finite-strain terms are O(eps)); for J2, neo-Hookean and Mooney-Rivlin.
  subroutine test_small_strain_hooke()
    type(material_t) :: mat
    real(wp) :: hist_old(NHIST), hist_new(NHIST), tau(3,3), lateral, strain, j
    integer :: m
    logical :: ok
    character(len=32) :: tag
    strain = 1.0e-6_wp
    do m = 1, 3
      select case (m)
      case (1)
        mat = linear_steel()
        tag = 'Hooke limit, J2'
      case (2)
        mat = elastic_steel()
        tag = 'Hooke limit, neo-Hookean'
      case (3)
        mat = rubber(0.4_wp, 0.1_wp)
        tag = 'Hooke limit, Mooney-Rivlin'
      end select
      call material_state_init(hist_old)
      lateral = 1.0_wp
      ! lateral residual 1e-7 E eps: above the round-off of kappa (J^2 - 1) at J - 1 ~ 1e-7
      call uniaxial_step(mat, 1.0_wp + strain, lateral, hist_old, hist_new, tau, &
                         1.0e-7_wp*mat%young*strain, ok)
      j = (1.0_wp + strain)*lateral**2
      call check(ok, trim(tag)//': lateral stress solved')
      call check_close(tau(1,1)/j, mat%young*strain, 1.0e-5_wp, trim(tag)// &
                       ': sigma = E eps at eps = 1e-6')
      call check_close(lateral - 1.0_wp, -mat%poisson*strain, 1.0e-5_wp, trim(tag)// &
                       ': lateral strain = -nu eps')
      call check(hist_new(HIST_ALPHA) == 0.0_wp, trim(tag)//': no plastic strain')
    end do
  end subroutine test_small_strain_hooke

  ! ---------------------------------------------------------------- 2 simple shear

  !> Simple shear F = I + gamma e1 (x) e2. Neo-Hookean: tau_12 = mu gamma, tau_11 = mu gamma^2,
  !> tau_22 = tau_33 = 0 exactly (J = 1). J2: mu gamma while elastic, then von Mises = K(alpha).
  subroutine test_simple_shear()
    type(material_t) :: mat
    real(wp) :: hist_old(NHIST), hist_new(NHIST), tau(3,3), f(3,3), gamma, mu, speed
    real(wp) :: worst, worst_elastic, k_alpha
    type(status_t) :: status
    integer :: i, step, n_plastic
    mat = elastic_steel()
    mu = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
    call material_state_init(hist_old)
    worst = 0.0_wp
    do i = 1, 4
      gamma = 0.25_wp*i
      f = IDENTITY
      f(1,2) = gamma
      call material_update(mat, curves, f, hist_old, hist_new, tau, sound_speed=speed, &
                           status=status)
      worst = max(worst, abs(tau(1,2) - mu*gamma)/(mu*gamma), abs(tau(2,1) - mu*gamma)/(mu*gamma), &
                  abs(tau(1,1) - mu*gamma**2)/(mu*gamma**2), abs(tau(2,2))/mu, abs(tau(3,3))/mu)
    end do
    ! round-off only: ln J = 0 exactly and b is formed with a few operations
    call check(worst < 1.0e-14_wp, 'neo-Hookean simple shear: tau_12 = mu gamma, tau_11 = mu '// &
               'gamma^2 for gamma up to 1', 'worst '//rtoa(worst))
    ! J2 with linear hardening and perfectly plastic
    do i = 1, 2
      mat = linear_steel()
      if (i == 2) mat%tangent_modulus = 0.0_wp
      mu = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
      call material_state_init(hist_old)
      worst = 0.0_wp
      worst_elastic = 0.0_wp
      n_plastic = 0
      do step = 1, 100
        ! elastic up to gamma = 0.0016 (yield at sqrt(3) mu gamma = 250: gamma = 0.00179)
        gamma = 0.0004_wp*min(step, 4) + 0.005_wp*max(step - 4, 0)
        f = IDENTITY
        f(1,2) = gamma
        call material_update(mat, curves, f, hist_old, hist_new, tau, sound_speed=speed, &
                             status=status)
        hist_old = hist_new
        if (hist_new(HIST_ALPHA) > 0.0_wp) then
          n_plastic = n_plastic + 1
          k_alpha = yield_of(mat, hist_new(HIST_ALPHA))
          worst = max(worst, abs(von_mises(tau) - k_alpha)/k_alpha)
        else
          worst_elastic = max(worst_elastic, abs(tau(1,2) - mu*gamma)/(mu*gamma))
        end if
      end do
      call check(n_plastic == 96 .and. status%ok, 'J2 simple shear ETAN='// &
                 rtoa(mat%tangent_modulus)//': 4 elastic steps, then plastic')
      call check(worst_elastic < 1.0e-13_wp, 'J2 simple shear ETAN='// &
                 rtoa(mat%tangent_modulus)//': tau_12 = mu gamma while elastic')
      ! return-map tolerance 1e-13
      call check(worst < 1.0e-11_wp, 'J2 simple shear ETAN='//rtoa(mat%tangent_modulus)// &
                 ': von Mises of tau = K(alpha) while plastic', 'worst '//rtoa(worst))
    end do
  end subroutine test_simple_shear

  ! ---------------------------------------------------------------- 3 objectivity

  !> The same path with F -> Q_k F_k, Q_k a rotation changing every step (and a constant one):
  !> tau -> Q tau Q^T, the same alpha and the same (Lagrangian) Cbar_p^-1 at every step,
  !> det be_bar = 1 on the rotated path.
  subroutine test_objectivity()
    type(material_t) :: mat
    real(wp) :: hist_a(NHIST), hist_b(NHIST), new_a(NHIST), new_b(NHIST)
    real(wp) :: tau_a(3,3), tau_b(3,3), f(3,3), q(3,3), be(3,3), direction(3,3), t, speed
    real(wp) :: cp_a(3,3), cp_b(3,3)
    real(wp) :: worst_tau, worst_alpha, worst_det, worst_cp, scale
    type(status_t) :: status_a, status_b
    integer :: m, step, variant
    character(len=64) :: tag
    direction = reshape([0.3_wp, 0.05_wp, 0.0_wp, 0.1_wp, -0.1_wp, 0.02_wp, 0.0_wp, 0.08_wp, &
                         -0.12_wp], [3, 3])
    do m = 1, 6
      select case (m)
      case (1)
        mat = linear_steel()
      case (2)
        mat = power_law_steel()
      case (3)
        mat = table_steel()
      case (4)
        mat = curve_steel()
      case (5)
        mat = elastic_steel()
      case (6)
        mat = rubber(0.4_wp, 0.1_wp)
      end select
      do variant = 1, 2
        write(tag, '(a,i0,a)') 'objectivity, material ', mat%id, &
            merge(', rotation varying ', ', constant rotation', variant == 1)
        call material_state_init(hist_a)
        call material_state_init(hist_b)
        worst_tau = 0.0_wp
        worst_alpha = 0.0_wp
        worst_det = 0.0_wp
        worst_cp = 0.0_wp
        do step = 1, 30
          t = real(step, wp)/30.0_wp
          f = IDENTITY + t*direction
          if (variant == 1) then
            q = rotation([1.0_wp, 2.0_wp, 3.0_wp], 0.2_wp*step)
          else
            q = rotation([-1.0_wp, 0.5_wp, 0.2_wp], 1.3_wp)
          end if
          call material_update(mat, curves, f, hist_a, new_a, tau_a, sound_speed=speed, &
                               status=status_a)
          call material_update(mat, curves, matmul(q, f), hist_b, new_b, tau_b, &
                               sound_speed=speed, status=status_b)
          hist_a = new_a
          hist_b = new_b
          scale = max(frobenius_norm(tau_a), 1.0_wp)
          worst_tau = max(worst_tau, maxval(abs(tau_b - matmul(q, matmul(tau_a, &
                                                transpose(q)))))/scale)
          worst_alpha = max(worst_alpha, abs(new_a(HIST_ALPHA) - new_b(HIST_ALPHA))/ &
                            max(new_a(HIST_ALPHA), 1.0e-3_wp))
          call state_elastic_strain(new_b, matmul(q, f), be)
          call state_plastic_metric(new_a, cp_a)
          call state_plastic_metric(new_b, cp_b)
          worst_cp = max(worst_cp, maxval(abs(cp_b - cp_a)))
          if (mat%kind /= MAT_ELASTIC .and. mat%kind /= MAT_MOONEY_RIVLIN) &
            worst_det = max(worst_det, abs(determinant(be) - 1.0_wp))
        end do
        call check(status_a%ok .and. status_b%ok, trim(tag)//': updates succeed')
        ! round-off of the products with Q, F_n^-1 and the return map, relative to |tau|
        call check(worst_tau < 1.0e-12_wp, trim(tag)//': tau -> Q tau Q^T', &
                   'worst '//rtoa(worst_tau))
        call check(worst_alpha < 1.0e-12_wp, trim(tag)//': same alpha', &
                   'worst '//rtoa(worst_alpha))
        call check(worst_det < 1.0e-12_wp, trim(tag)//': det be_bar = 1 on the rotated path', &
                   'worst '//rtoa(worst_det))
        call check(worst_cp < 1.0e-12_wp, trim(tag)//': the same Cbar_p^-1 on both paths', &
                   'worst '//rtoa(worst_cp))
        if (mat%kind == MAT_PIECEWISE_LINEAR .or. mat%kind == MAT_POWER_LAW) &
          call check(hist_a(HIST_ALPHA) > 0.1_wp, trim(tag)//': path is plastic (alpha = '// &
                     rtoa(hist_a(HIST_ALPHA))//')')
      end do
    end do
  end subroutine test_objectivity

  ! ---------------------------------------------------------------- 5 tangents

  !> c_tau against central differences: for dF = h F, h = e_k (x) e_l, the derivative of tau
  !> is c : sym(h) + h tau + tau h^T. Relative error (max over entries / max |c|) < 1e-6:
  !> with step 1e-6 the truncation is ~1e-12 and the round-off ~1e-16 |tau|/(1e-6 |c|).
  subroutine test_tangents()
    real(wp) :: f_general(3,3), f_large(3,3), f_path(3,3), f_small(3,3)
    f_general = reshape([1.1_wp, 0.05_wp, -0.08_wp, 0.2_wp, 0.9_wp, 0.1_wp, -0.1_wp, 0.15_wp, &
                         1.05_wp], [3, 3])
    f_large = reshape([1.5_wp, 0.1_wp, 0.0_wp, 0.3_wp, 0.8_wp, 0.1_wp, 0.0_wp, 0.2_wp, 0.9_wp], &
                      [3, 3])
    f_small = IDENTITY + 4.0e-4_wp*reshape([1.0_wp, 0.3_wp, -0.2_wp, 0.5_wp, -0.4_wp, 0.1_wp, &
                                            0.2_wp, 0.6_wp, -0.3_wp], [3, 3])
    ! plastic states: after a plastic pre-path to F_path, a further step in another direction
    f_path = IDENTITY + reshape([0.06_wp, 0.01_wp, 0.0_wp, 0.02_wp, -0.03_wp, 0.0_wp, 0.0_wp, &
                                 0.01_wp, -0.03_wp], [3, 3])
    call tangent_case(elastic_steel(), 'neo-Hookean', IDENTITY, f_general, 0)
    call tangent_case(rubber(0.4_wp, 0.1_wp), 'Mooney-Rivlin', IDENTITY, f_large, 0)
    call tangent_case(rubber(0.5_wp, 0.0_wp), 'Mooney-Rivlin B = 0', IDENTITY, f_large, 0)
    call tangent_case(linear_steel(), 'J2 elastic at small strain', IDENTITY, f_small, 0)
    call tangent_case(linear_steel(), 'J2 elastic unloading after plastic flow', f_path, &
                      matmul(IDENTITY - 2.0e-4_wp*reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
                      -0.5_wp, 0.0_wp, 0.0_wp, 0.0_wp, -0.5_wp], [3, 3]), f_path), -1)
    call tangent_case(linear_steel(), 'J2 plastic, linear hardening', f_path, &
                      plastic_step(f_path), 1)
    call tangent_case(perfect_steel(), 'J2 plastic, no hardening', f_path, plastic_step(f_path), 1)
    call tangent_case(power_law_steel(), 'J2 plastic, power law', f_path, plastic_step(f_path), 1)
    call tangent_case(table_steel(), 'J2 plastic, EPS/ES table', f_path, plastic_step(f_path), 1)
    call tangent_case(curve_steel(), 'J2 plastic, LCSS curve', f_path, plastic_step(f_path), 1)
    call tangent_case(linear_steel(), 'J2 plastic, large rotation and strain', f_path, &
                      matmul(f_large, f_path), 1)
  end subroutine test_tangents

  !> *MAT_024 with ETAN = 0.
  type(material_t) function perfect_steel() result(mat)
    mat = linear_steel()
    mat%tangent_modulus = 0.0_wp
  end function perfect_steel

  !> A further plastic step from F_path in a different (shear) direction.
  function plastic_step(f_path) result(f)
    real(wp), intent(in) :: f_path(3,3)
    real(wp) :: f(3,3)
    f = matmul(IDENTITY + reshape([0.004_wp, 0.003_wp, -0.001_wp, 0.006_wp, -0.002_wp, &
                                   0.002_wp, 0.001_wp, 0.002_wp, -0.001_wp], [3, 3]), f_path)
  end function plastic_step

  !> One tangent check: hist after the path I -> f_path (20 steps), then c_tau at f_new
  !> against the Lie-derivative identity. expect_plastic: 1 plastic step, -1 elastic step
  !> after plastic flow, 0 no requirement.
  subroutine tangent_case(mat, name, f_path, f_new, expect_plastic)
    type(material_t), intent(in) :: mat
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: f_path(3,3), f_new(3,3)
    integer, intent(in) :: expect_plastic
    real(wp) :: hist(NHIST), hist_new(NHIST), tau(3,3), c(3,3,3,3), tau_p(3,3), tau_m(3,3)
    real(wp) :: h(3,3), fd(3,3), expected(3,3), sym_h(3,3), speed, eps, worst, scale, minor
    real(wp) :: c_dummy(3,3,3,3)
    type(status_t) :: status
    integer :: step, k, l, i, jj
    call material_state_init(hist)
    do step = 1, 20
      call material_update(mat, curves, IDENTITY + real(step, wp)/20.0_wp*(f_path - IDENTITY), &
                           hist, hist_new, tau, sound_speed=speed, status=status)
      hist = hist_new
    end do
    call material_update(mat, curves, f_new, hist, hist_new, tau, c, speed, status)
    call check(status%ok, trim(name)//': update succeeds')
    if (expect_plastic == 1) call check(hist_new(HIST_ALPHA) > hist(HIST_ALPHA) + 1.0e-4_wp, &
        trim(name)//': the step is plastic')
    if (expect_plastic == -1) call check(hist(HIST_ALPHA) > 0.0_wp .and. &
        hist_new(HIST_ALPHA) == hist(HIST_ALPHA), trim(name)//': the step is elastic')
    eps = 1.0e-6_wp
    scale = maxval(abs(c))
    worst = 0.0_wp
    do l = 1, 3
      do k = 1, 3
        h = 0.0_wp
        h(k,l) = 1.0_wp
        sym_h = 0.5_wp*(h + transpose(h))
        call material_update(mat, curves, f_new + eps*matmul(h, f_new), hist, hist_new, tau_p, &
                             c_dummy, speed, status)
        call material_update(mat, curves, f_new - eps*matmul(h, f_new), hist, hist_new, tau_m, &
                             c_dummy, speed, status)
        fd = (tau_p - tau_m)/(2.0_wp*eps)
        do jj = 1, 3
          do i = 1, 3
            expected(i,jj) = sum(c(i,jj,:,:)*sym_h)
          end do
        end do
        expected = expected + matmul(h, tau) + matmul(tau, transpose(h))
        worst = max(worst, maxval(abs(fd - expected))/scale)
      end do
    end do
    call check(worst < 1.0e-6_wp, trim(name)//': c_tau matches central differences of tau(F)', &
               'relative error '//rtoa(worst))
    minor = max(maxval(abs(c - reshape(c, [3, 3, 3, 3], order=[2, 1, 3, 4]))), &
                maxval(abs(c - reshape(c, [3, 3, 3, 3], order=[1, 2, 4, 3]))))/scale
    call check(minor < 1.0e-14_wp, trim(name)//': c_tau has the minor symmetries')
  end subroutine tangent_case

  ! ---------------------------------------------------------------- 6 failures

  !> det F <= 0 fails with a message for every law; *MAT_RIGID and unknown kinds fail; the
  !> optional tangent may be left out.
  subroutine test_failures()
    type(material_t) :: mats(6), mat
    real(wp) :: hist_old(NHIST), hist_new(NHIST), tau(3,3), f(3,3), speed
    type(status_t) :: status
    integer :: m, variant
    logical :: all_failed
    mats = [linear_steel(), power_law_steel(), table_steel(), curve_steel(), elastic_steel(), &
            rubber(0.4_wp, 0.1_wp)]
    call material_state_init(hist_old)
    all_failed = .true.
    do m = 1, size(mats)
      do variant = 1, 2
        f = IDENTITY
        if (variant == 1) then
          f(1,1) = -1.0_wp
        else
          f(2,:) = 0.0_wp
        end if
        call material_update(mats(m), curves, f, hist_old, hist_new, tau, sound_speed=speed, &
                             status=status)
        if (status%ok) then
          all_failed = .false.
        else if (.not. allocated(status%message)) then
          all_failed = .false.
        else if (index(status%message, 'det F') == 0) then
          all_failed = .false.
        end if
        if (any(tau /= 0.0_wp)) all_failed = .false.
      end do
    end do
    call check(all_failed, 'det F < 0 and det F = 0: status false with a message, zero '// &
               'stress, for every law')
    if (allocated(status%message)) call check(index(status%message, 'material 6') > 0, &
        'message names the material: "'//status%message//'"')
    mat = linear_steel()
    mat%kind = MAT_RIGID
    call material_update(mat, curves, IDENTITY, hist_old, hist_new, tau, sound_speed=speed, &
                         status=status)
    call check(.not. status%ok, '*MAT_RIGID has no stress update (status false)')
    mat%kind = 999
    call material_update(mat, curves, IDENTITY, hist_old, hist_new, tau, sound_speed=speed, &
                         status=status)
    call check(.not. status%ok, 'unknown material kind: status false')
    ! wave speed at F = I: sqrt((K + 4/3 G)/rho0)
    mat = linear_steel()
    call material_update(mat, curves, IDENTITY, hist_old, hist_new, tau, sound_speed=speed, &
                         status=status)
    call check_close(speed, sqrt(mat%young*(1.0_wp - mat%poisson)/((1.0_wp + mat%poisson)* &
                     (1.0_wp - 2.0_wp*mat%poisson)*mat%density)), 1.0e-14_wp, &
                     'J2 wave speed at F = I is sqrt((K + 4/3 G)/rho0)')
    mat = elastic_steel()
    call material_update(mat, curves, IDENTITY, hist_old, hist_new, tau, sound_speed=speed, &
                         status=status)
    call check_close(speed, sqrt(mat%young*(1.0_wp - mat%poisson)/((1.0_wp + mat%poisson)* &
                     (1.0_wp - 2.0_wp*mat%poisson)*mat%density)), 1.0e-14_wp, &
                     'neo-Hookean wave speed at F = I is sqrt((K + 4/3 G)/rho0)')
    mat = rubber(0.4_wp, 0.1_wp)
    call material_update(mat, curves, IDENTITY, hist_old, hist_new, tau, sound_speed=speed, &
                         status=status)
    call check_close(speed, sqrt(mat%young*(1.0_wp - mat%poisson)/((1.0_wp + mat%poisson)* &
                     (1.0_wp - 2.0_wp*mat%poisson)*mat%density)), 1.0e-14_wp, &
                     'Mooney-Rivlin wave speed at F = I is sqrt((K + 4/3 G)/rho0)')
  end subroutine test_failures

  ! ---------------------------------------------------------------- 9 erosion criteria

  !> Voigt (xx yy zz xy yz zx) of a symmetric matrix.
  function voigt(a) result(v)
    real(wp), intent(in) :: a(3,3)
    real(wp) :: v(6)
    v = [a(1,1), a(2,2), a(3,3), a(1,2), a(2,3), a(1,3)]
  end function voigt

  !> Principal values of R diag R^T are the diagonal, largest first (distinct, two equal, all
  !> equal); each *MAT_ADD_EROSION criterion, alone, is met just above its limit and not just
  !> below it on a rotated state (stretches lambda_i: F = R diag(lambda) R^T, tau = J sigma with
  !> sigma = R diag(s) R^T), and NCS counts the criteria met.
  subroutine test_erosion_criteria()
    real(wp), parameter :: AXIS(3) = [1.0_wp, 2.0_wp, 2.0_wp]/3.0_wp
    real(wp) :: r(3,3), lam(3), s(3), f(3,3), tau(6), j, value(9), strain(3), dev(3), got(3)
    real(wp) :: diag(3,3), cases(3,3)
    type(material_t) :: mat
    integer :: c, k
    logical :: ok
    r = rotation(AXIS, 0.7_wp)
    cases = reshape([3.0_wp, -1.0_wp, 0.5_wp, 2.0_wp, 2.0_wp, -4.0_wp, 1.5_wp, 1.5_wp, &
                     1.5_wp], [3, 3])
    do c = 1, 3
      diag = 0.0_wp
      do k = 1, 3
        diag(k,k) = cases(k,c)
      end do
      got = symmetric_eigenvalues(voigt(matmul(r, matmul(diag, transpose(r)))))
      lam = cases(:,c)
      call sort_descending(lam)
      call check_close(got, lam, 1.0e-14_wp*maxval(abs(lam)), &
                       'principal values of a rotated diagonal tensor, case '//itoa(c))
    end do
    ! a state: stretches lam, Cauchy principal stresses s, time 2e-3
    lam = [1.08_wp, 0.97_wp, 0.99_wp]
    s = [150.0_wp, -40.0_wp, 20.0_wp]
    f = matmul(r, matmul(diagonal(lam), transpose(r)))
    j = product(lam)
    tau = j*voigt(matmul(r, matmul(diagonal(s), transpose(r))))
    strain = log(lam)
    dev = strain - sum(strain)/3.0_wp
    value(EROSION_MXPRES) = -sum(s)/3.0_wp
    value(EROSION_MNEPS) = minval(strain)
    value(EROSION_EFFEPS) = sqrt(2.0_wp/3.0_wp*sum(dev**2))
    value(EROSION_VOLEPS) = sum(strain)
    value(EROSION_MNPRES) = -sum(s)/3.0_wp
    value(EROSION_SIGP1) = maxval(s)
    value(EROSION_SIGVM) = sqrt(1.5_wp*sum((s - sum(s)/3.0_wp)**2))
    value(EROSION_MXEPS) = maxval(strain)
    value(EROSION_FAILTM) = 2.0e-3_wp
    mat = elastic_steel()
    mat%add_erosion = .true.
    mat%erosion_conditions = 1
    do c = 1, 9
      mat%erosion_used = .false.
      mat%erosion_used(c) = .true.
      ! "greater than" criteria are met with the limit just below the value, "less than"
      ! ones (MNEPS, MNPRES, a negative VOLEPS) with the limit just above it
      ok = .true.
      do k = -1, 1, 2
        mat%erosion_limit(c) = value(c) + real(k, wp)*(1.0e-6_wp*abs(value(c)) + 1.0e-9_wp)
        ok = ok .and. (erosion_criteria_met(mat, reshape(f, [9]), tau, j, 2.0e-3_wp) .eqv. &
                       ((k == -1) .neqv. (c == EROSION_MNEPS .or. c == EROSION_MNPRES .or. &
                                          (c == EROSION_VOLEPS .and. value(c) < 0.0_wp))))
      end do
      call check(ok, '*MAT_ADD_EROSION criterion '//itoa(c)//' at its value '// &
                 rtoa(value(c))//': met on its side of the limit, not on the other')
    end do
    ! NCS 2: MXEPS met, SIGP1 not: no failure; both met: failure
    mat%erosion_used = .false.
    mat%erosion_used([EROSION_MXEPS, EROSION_SIGP1]) = .true.
    mat%erosion_conditions = 2
    mat%erosion_limit(EROSION_MXEPS) = 0.5_wp*value(EROSION_MXEPS)
    mat%erosion_limit(EROSION_SIGP1) = 2.0_wp*value(EROSION_SIGP1)
    call check(.not. erosion_criteria_met(mat, reshape(f, [9]), tau, j, 0.0_wp), &
               'NCS 2: one criterion met of two: no failure')
    mat%erosion_limit(EROSION_SIGP1) = 0.5_wp*value(EROSION_SIGP1)
    call check(erosion_criteria_met(mat, reshape(f, [9]), tau, j, 0.0_wp), &
               'NCS 2: both criteria met: failure')
  end subroutine test_erosion_criteria

  !> diag(d)
  function diagonal(d) result(a)
    real(wp), intent(in) :: d(3)
    real(wp) :: a(3,3)
    integer :: k
    a = 0.0_wp
    do k = 1, 3
      a(k,k) = d(k)
    end do
  end function diagonal

  !> Sort three values, largest first.
  subroutine sort_descending(v)
    real(wp), intent(inout) :: v(3)
    integer :: a, b
    real(wp) :: t
    do a = 1, 2
      do b = a + 1, 3
        if (v(b) > v(a)) then
          t = v(a)
          v(a) = v(b)
          v(b) = t
        end if
      end do
    end do
  end subroutine sort_descending

  ! ---------------------------------------------------------------- 10 Johnson-Cook damage

  !> *MAT_015, perfectly plastic (A, B = 0), C = 0, heated by its plastic work (CP, TM; M = 50
  !> so that the softening (T*)^50 stays below 1e-13), at a fixed rate 1000 EPSO, in uniaxial
  !> tension (triaxiality 1/3): T* = k alpha with k = A/(rho CP (TM - TR)), so
  !> D(alpha) = int da/(eps0 R (1 + D5 k a)) = ln(1 + D5 k alpha)/(eps0 R D5 k) with
  !> eps0 = D1 + D2 exp(D3/3) and R = 1 + D4 ln 1000. The update sums the increments at the
  !> step's end temperature (a right Riemann sum): relative error <= D5 k d_alpha/2 = 2.7e-4
  !> at the steps below, so 1e-3 can fail. Also: compression (triaxiality -1/3) gives the
  !> larger eps_f of exp(+D3/3); no damage without plastic flow.
  subroutine test_johnson_cook_damage()
    type(material_t) :: mat
    real(wp) :: hist_old(NHIST), hist_new(NHIST), tau(3,3), lateral, stretch, k, eps0, rr
    real(wp) :: expected, alpha
    integer :: step
    logical :: ok, all_ok
    mat = johnson_cook_steel()
    mat%jc_m = 50.0_wp
    mat%melt_temperature = 1800.0_wp
    mat%room_temperature = 300.0_wp
    mat%heat_capacity = 4.77e7_wp
    mat%jc_fails = .true.
    mat%jc_damage = [0.05_wp, 0.5_wp, -1.5_wp, 0.01_wp, 1.0_wp]
    mat%jc_min_failure_strain = 1.0e-6_wp
    k = mat%jc_a/(mat%density*mat%heat_capacity*(mat%melt_temperature - mat%room_temperature))
    rr = 1.0_wp + mat%jc_damage(4)*log(1000.0_wp)
    eps0 = mat%jc_damage(1) + mat%jc_damage(2)*exp(mat%jc_damage(3)/3.0_wp)
    call material_state_init(hist_old)
    lateral = 1.0_wp
    all_ok = .true.
    do step = 1, 300
      stretch = exp(0.001_wp*real(step, wp))
      call uniaxial_step(mat, stretch, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok, &
                         rate=1000.0_wp)
      all_ok = all_ok .and. ok
      hist_old = hist_new
    end do
    alpha = hist_new(HIST_ALPHA)
    expected = log(1.0_wp + mat%jc_damage(5)*k*alpha)/(eps0*rr*mat%jc_damage(5)*k)
    call check(all_ok .and. alpha > 0.29_wp, 'Johnson-Cook damage: uniaxial path to alpha = '// &
               rtoa(alpha))
    call check_close(hist_new(HIST_DAMAGE), expected, 1.0e-3_wp*expected, 'Johnson-Cook '// &
                     'damage D = ln(1 + D5 k alpha)/(eps0 R D5 k) = '//rtoa(expected)// &
                     ' (heated, rate 1000 EPSO, triaxiality 1/3)')
    ! compression: triaxiality -1/3, no heating, no rate term: D = alpha/(D1 + D2 exp(-D3/3))
    mat%heat_capacity = 0.0_wp
    call material_state_init(hist_old)
    lateral = 1.0_wp
    do step = 1, 100
      stretch = exp(-0.002_wp*real(step, wp))
      call uniaxial_step(mat, stretch, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok)
      hist_old = hist_new
    end do
    alpha = hist_new(HIST_ALPHA)
    expected = alpha/(mat%jc_damage(1) + mat%jc_damage(2)*exp(-mat%jc_damage(3)/3.0_wp))
    call check_close(hist_new(HIST_DAMAGE), expected, 1.0e-9_wp*expected, 'Johnson-Cook '// &
                     'damage in compression: alpha/(D1 + D2 exp(-D3/3)) = '//rtoa(expected))
    ! elastic: no damage
    call material_state_init(hist_old)
    lateral = 1.0_wp
    call uniaxial_step(mat, 1.0005_wp, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok)
    call check(ok .and. hist_new(HIST_DAMAGE) == 0.0_wp .and. hist_new(HIST_ALPHA) == 0.0_wp, &
               'Johnson-Cook damage: none in an elastic step')
  end subroutine test_johnson_cook_damage

  !> *MAT_015 spall and kept failure (spall_stress), one point, PC = -100 MPa, against the same
  !> update without them: SPALL 1 caps the tension at p = PC and leaves the deviator (and any
  !> compression) alone; SPALL 3 marks a point whose p < PC, which then carries no tension and,
  !> compressed again, only the pressure of the plain update (no deviator); SPALL 2 marks at
  !> sigma_max >= -PC, not below; EROD /= 0 keeps a point whose damage reached 1 (not eroded:
  !> point_fails is false) with the plain update's pressure, tension included, and no deviator;
  !> a marked point's history is frozen.
  subroutine test_johnson_cook_spall()
    type(material_t) :: mat
    real(wp) :: hist0(NHIST), hist1(NHIST), hist2(NHIST), hist3(NHIST), tau(3,3), plain(3,3), j
    real(wp) :: f_tension(3,3), f_compression(3,3), f_small(3,3)
    mat = johnson_cook_steel()
    mat%pressure_cutoff = -100.0_wp
    call material_state_init(hist0)
    f_tension = IDENTITY
    f_tension(1, 1) = 1.002_wp                  ! plain p = -333 MPa < PC
    f_compression = IDENTITY
    f_compression(1, 1) = 0.995_wp
    f_small = IDENTITY
    f_small(1, 1) = 1.0003_wp                   ! uniaxial strain: sigma_xx 81, p -50 MPa
    ! SPALL 1: the cutoff
    mat%spall = SPALL_PRESSURE_CUTOFF
    call spall_update(mat, f_tension, hist0, hist1, plain, .false.)
    call spall_update(mat, f_tension, hist0, hist1, tau, .true.)
    j = determinant(f_tension)
    call check(mean_pressure(plain, j) < mat%pressure_cutoff, 'spall 1: the plain tension is beyond'// &
               ' PC (p = '//rtoa(mean_pressure(plain, j))//')')
    call check_close(mean_pressure(tau, j), mat%pressure_cutoff, 1.0e-12_wp*100.0_wp, &
                     'spall 1: p = PC under tension beyond it')
    call check(maxval(abs(deviator(tau) - deviator(plain))) <= 1.0e-12_wp*maxval(abs(plain)), &
               'spall 1: the deviatoric stress untouched')
    call check(hist1(HIST_SPALL) == POINT_INTACT, 'spall 1: nothing remembered')
    call spall_update(mat, f_compression, hist0, hist1, plain, .false.)
    call spall_update(mat, f_compression, hist0, hist1, tau, .true.)
    call check(all(tau == plain), 'spall 1: compression untouched')
    ! SPALL 3: hydrostatic spall, then compression only
    mat%spall = SPALL_HYDROSTATIC
    call spall_update(mat, f_small, hist0, hist1, tau, .true.)
    call check(hist1(HIST_SPALL) == POINT_INTACT, 'spall 3: no spall while p > PC')
    call spall_update(mat, f_tension, hist0, hist1, tau, .true.)
    call check(hist1(HIST_SPALL) == POINT_SPALLED .and. all(tau == 0.0_wp), &
               'spall 3: spalled at p < PC, no tension left')
    call spall_update(mat, f_compression, hist1, hist2, tau, .true.)
    call spall_update(mat, f_compression, hist0, hist3, plain, .false.)
    j = determinant(f_compression)
    call check(maxval(abs(deviator(tau))) == 0.0_wp .and. abs(mean_pressure(tau, j) - &
               mean_pressure(plain, j)) <= 1.0e-12_wp*abs(mean_pressure(plain, j)) .and. &
               mean_pressure(tau, j) > 0.0_wp, 'spall 3: compressed again, the plain pressure '// &
               rtoa(mean_pressure(plain, j))//' and no deviator')
    call check(all(hist2 == hist1), 'spall 3: the spalled point''s history frozen')
    ! SPALL 2: the largest principal stress
    mat%spall = SPALL_PRINCIPAL
    call spall_update(mat, f_small, hist0, hist1, plain, .false.)
    j = determinant(f_small)
    call check(maxval(symmetric_eigenvalues(voigt(plain)/j)) < 100.0_wp .and. &
               maxval(symmetric_eigenvalues(voigt(plain)/j)) > 50.0_wp, 'spall 2: the small '// &
               'step''s sigma_max '//rtoa(maxval(symmetric_eigenvalues(voigt(plain)/j)))// &
               ' below -PC')
    call spall_update(mat, f_small, hist0, hist1, tau, .true.)
    call check(hist1(HIST_SPALL) == POINT_INTACT .and. all(tau == plain), &
               'spall 2: not spalled below -PC, stress untouched')
    f_small(1, 1) = 1.0005_wp                   ! sigma_xx 135 MPa, p -83 MPa > PC
    call spall_update(mat, f_small, hist0, hist1, tau, .true.)
    call check(hist1(HIST_SPALL) == POINT_SPALLED .and. all(tau == 0.0_wp), &
               'spall 2: spalled at sigma_max >= -PC (while p > PC), no tension left')
    ! EROD /= 0: failed points kept with their pressure
    mat%spall = 0
    mat%jc_fails = .true.
    mat%jc_keep_failed = .true.
    mat%jc_damage = [0.01_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    hist0(HIST_DAMAGE) = 1.0_wp
    call spall_update(mat, f_tension, hist0, hist1, plain, .false.)
    call spall_update(mat, f_tension, hist0, hist1, tau, .true.)
    j = determinant(f_tension)
    call check(hist1(HIST_SPALL) == POINT_FAILED_KEPT .and. &
               maxval(abs(deviator(tau))) == 0.0_wp .and. &
               abs(mean_pressure(tau, j) - mean_pressure(plain, j)) <= 1.0e-12_wp*abs(mean_pressure(plain, j)), &
               'EROD: a failed point kept with its pressure '//rtoa(mean_pressure(tau, j))// &
               ' (tension too), no deviator')
    call check(.not. point_fails(mat, hist1(HIST_ALPHA), hist1(HIST_DAMAGE), &
                                 reshape(f_tension, [9]), [tau(1,1), tau(2,2), tau(3,3), &
                                 tau(1,2), tau(2,3), tau(3,1)], j, 0.0_wp), &
               'EROD: the failed point is not eroded')
  end subroutine test_johnson_cook_spall

  !> One update of mat from hist_a, with or without the spall treatment (test_johnson_cook_spall).
  subroutine spall_update(mat, f, hist_a, hist_b, tau_out, with_spall)
    type(material_t), intent(in) :: mat         !< the material
    real(wp), intent(in) :: f(3,3)              !< F_{n+1}
    real(wp), intent(in) :: hist_a(NHIST)       !< history at t_n
    real(wp), intent(out) :: hist_b(NHIST)      !< history at t_{n+1}
    real(wp), intent(out) :: tau_out(3,3)       !< Kirchhoff stress
    logical, intent(in) :: with_spall           !< spall=
    type(status_t) :: status
    real(wp) :: sound
    call material_update(mat, curves, f, hist_a, hist_b, tau_out, sound_speed=sound, &
                         status=status, spall=with_spall)
    call check(status%ok, 'spall: update succeeds')
  end subroutine spall_update

  !> p = -tr(tau)/(3 J).
  pure real(wp) function mean_pressure(t, jac)
    real(wp), intent(in) :: t(3,3), jac         !< Kirchhoff stress, J
    mean_pressure = -(t(1,1) + t(2,2) + t(3,3))/(3.0_wp*jac)
  end function mean_pressure

  ! ---------------------------------------------------------------- 11 VP = 1

  !> *MAT_024 with Cowper-Symonds C = 40 /s, P = 5 and VP = 1: a uniaxial step from the virgin
  !> state to a stretch of 1.01 in dt = 1e-4 s ends on the viscoplastic yield surface, the von
  !> Mises Kirchhoff stress (SIGY + Ep alpha)(1 + (alpha/(C dt))^(1/P)) of its plastic strain
  !> alpha (1e-10); the same step with dt ten times longer flows at a lower stress; VP = 0
  !> (no rate given) gives SIGY + Ep alpha.
  subroutine test_viscoplastic()
    type(material_t) :: mat
    real(wp) :: hist_old(NHIST), hist_new(NHIST), tau(3,3), lateral, alpha, q, want, q_slow
    real(wp) :: dt
    logical :: ok
    mat = linear_steel()
    mat%cowper_c = 40.0_wp
    mat%cowper_p = 5.0_wp
    mat%vp = 1.0_wp
    dt = 1.0e-4_wp
    call material_state_init(hist_old)
    lateral = 1.0_wp
    call uniaxial_step(mat, 1.01_wp, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok, &
                       rate=100.0_wp, dt=dt)
    alpha = hist_new(HIST_ALPHA)
    q = von_mises(tau)
    want = (mat%yield_stress + plastic_modulus(mat)*alpha)* &
           (1.0_wp + (alpha/(mat%cowper_c*dt))**(1.0_wp/mat%cowper_p))
    call check(ok .and. alpha > 0.0_wp, 'VP = 1: the step flows (alpha = '//rtoa(alpha)//')')
    call check_close(q, want, 1.0e-10_wp*want, 'VP = 1: von Mises tau = K(alpha) (1 + '// &
                     '(alpha/(C dt))^(1/P)) = '//rtoa(want)//' MPa')
    lateral = 1.0_wp
    call uniaxial_step(mat, 1.01_wp, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok, &
                       rate=10.0_wp, dt=10.0_wp*dt)
    q_slow = von_mises(tau)
    call check(ok .and. q_slow < q, 'VP = 1: the same strain in a ten times longer step flows '// &
               'at a lower stress ('//rtoa(q_slow)//' < '//rtoa(q)//' MPa)')
    ! *MAT_018 (SRC, SRP) likewise: K(alpha) of the power law times the plastic-rate factor
    block
      type(material_t) :: power
      real(wp) :: yield_stress, slope
      power = power_law_steel()
      power%cowper_c = 40.0_wp
      power%cowper_p = 5.0_wp
      power%vp = 1.0_wp
      lateral = 1.0_wp
      call uniaxial_step(power, 1.01_wp, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok, &
                         rate=100.0_wp, dt=dt)
      alpha = hist_new(HIST_ALPHA)
      call hardening_yield(HARDENING_POWER_LAW, power, curves, alpha, yield_stress, slope)
      want = yield_stress*(1.0_wp + (alpha/(power%cowper_c*dt))**(1.0_wp/power%cowper_p))
      call check_close(von_mises(tau), want, 1.0e-10_wp*want, '*MAT_018 VP = 1: von Mises '// &
                       'tau = K(alpha) (1 + (alpha/(C dt))^(1/P)) = '//rtoa(want)//' MPa')
    end block
    ! *MAT_003 (BETA 1: isotropic, no back stress), its own return: the same surface
    block
      type(material_t) :: kinematic
      kinematic = linear_steel()
      kinematic%kind = MAT_PLASTIC_KINEMATIC
      kinematic%beta = 1.0_wp
      kinematic%cowper_c = 40.0_wp
      kinematic%cowper_p = 5.0_wp
      kinematic%vp = 1.0_wp
      lateral = 1.0_wp
      call uniaxial_step(kinematic, 1.01_wp, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok, &
                         rate=100.0_wp, dt=dt)
      alpha = hist_new(HIST_ALPHA)
      want = (kinematic%yield_stress + plastic_modulus(kinematic)*alpha)* &
             (1.0_wp + (alpha/(kinematic%cowper_c*dt))**(1.0_wp/kinematic%cowper_p))
      call check(ok .and. alpha > 0.0_wp, '*MAT_003 VP = 1: the step flows')
      call check_close(von_mises(tau), want, 1.0e-10_wp*want, '*MAT_003 VP = 1 (BETA 1): von '// &
                       'Mises tau = (SIGY + Ep alpha)(1 + (alpha/(C dt))^(1/P)) = '// &
                       rtoa(want)//' MPa')
    end block
    mat%vp = 0.0_wp
    lateral = 1.0_wp
    call uniaxial_step(mat, 1.01_wp, lateral, hist_old, hist_new, tau, 1.0e-9_wp, ok)
    call check_close(von_mises(tau), mat%yield_stress + plastic_modulus(mat)* &
                     hist_new(HIST_ALPHA), 1.0e-10_wp*mat%yield_stress, &
                     'VP = 0 without a rate: von Mises tau = SIGY + Ep alpha')
  end subroutine test_viscoplastic

end program test_materials
