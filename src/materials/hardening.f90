!> Isotropic hardening laws of the J2 plasticity model: the uniaxial yield stress K(alpha)
!> and its slope K'(alpha) as functions of the equivalent plastic strain alpha.
!>
!> Laws (the dispatcher mefem_material_update picks the law from the material kind):
!> - HARDENING_POWER_LAW, *MAT_POWER_LAW_PLASTICITY (*MAT_018):
!>   K(alpha) = k (eps_yp + alpha)^n with k = mat%k_strength, n = mat%n_exponent and the
!>   strain offset eps_yp from SIGY as LS-DYNA defines it (see power_law_strain_offset):
!>     SIGY = 0          eps_yp = (E/k)^(1/(n-1)), where sigma = E eps meets sigma = k eps^n,
!>                       so the initial yield stress is E eps_yp;
!>     0 < SIGY < 0.02   eps_yp = SIGY (SIGY is read as the strain offset itself);
!>     SIGY >= 0.02      eps_yp = (SIGY/k)^(1/n), so that K(0) = SIGY.
!>   Source: the field description of SIGY in the LS-DYNA keyword manual as reproduced in
!>   ansys/pydyna (keyword_classes/auto/mat/mat_018.py: "LT.0.02: epsilon-yp = SIGY,
!>   GE.0.02: see manual") and the manual's remark for SIGY = 0 (intersection of the elastic
!>   line with the hardening curve, eps_yp = (E/k)^(1/(n-1))), the latter from memory of the
!>   manual, not re-read here. The 0.02 threshold is unit-dependent; it is LS-DYNA's rule and
!>   is kept so that LS-DYNA decks mean the same here.
!>   The seed paper's law sigma_y0 (1 + a alpha)^b is this law with k = sigma_y0 a^b, n = b,
!>   SIGY = sigma_y0 (then eps_yp = 1/a).
!> - HARDENING_LINEAR, *MAT_024 with SIGY and ETAN: K = SIGY + Ep alpha with the plastic
!>   modulus Ep = E ETAN/(E - ETAN) (ETAN is the slope of the uniaxial stress-total strain line).
!> - HARDENING_TABLE, *MAT_024 with EPS1..EPSn / ES1..ESn: K piecewise linear in alpha through
!>   the points (LS-DYNA: true stress vs effective plastic strain), extended linearly with the
!>   first/last segment's slope outside the table (as *DEFINE_CURVE is evaluated).
!> - HARDENING_CURVE, *MAT_024 with LCSS: K = curve_value(curve, alpha) of the yield stress
!>   vs effective plastic strain curve; K' the slope of the segment curve_value uses. LCSS a
!>   table of such curves by strain rate: the material passed in (rate_table_material) names
!>   the two curves around the rate and the weight of the upper one, and K, K' blend them.
!> - HARDENING_JOHNSON_COOK, *MAT_JOHNSON_COOK and *MAT_SIMPLIFIED_JOHNSON_COOK:
!>   K = A + B alpha^N, capped at SIGMAX (*MAT_098) when SIGMAX > 0; K' = N B alpha^(N-1),
!>   taken at alpha >= JC_SLOPE_STRAIN (for N < 1 the slope is infinite at alpha = 0: a
!>   finite, very large one serves the return map's Newton steps, which bisection guards).
!> Strain-rate effects scale K and K' by hardening_rate_factor(mat, curves, rate) of the
!> element's effective strain rate (LS-DYNA's VP = 0 form, doc/theory.md section 4): the LCSR
!> curve of *MAT_024 (scale against strain rate), else Cowper-Symonds 1 + (rate/C)^(1/P)
!> (*MAT_024 C, P; *MAT_018 and *MAT_003 SRC, SRP); Johnson-Cook 1 + C ln(rate/EPSO) for
!> rate > EPSO (1 below: LS-DYNA's quasi-static threshold).
!> At a table or curve point alpha = EPS_i the slope is that of the segment to the right.
module mefem_hardening
  use mefem_kinds, only: wp
  use mefem_model, only: material_t, curve_t, MAT_JOHNSON_COOK, MAT_SIMPLIFIED_JOHNSON_COOK, &
                         MAT_PIECEWISE_LINEAR, MAT_POWER_LAW, MAT_PLASTIC_KINEMATIC
  use mefem_curves, only: curve_value
  implicit none
  private

  integer, parameter, public :: HARDENING_POWER_LAW = 1   !< *MAT_018
  integer, parameter, public :: HARDENING_LINEAR = 2      !< *MAT_024 SIGY + ETAN
  integer, parameter, public :: HARDENING_TABLE = 3       !< *MAT_024 EPS/ES points
  integer, parameter, public :: HARDENING_CURVE = 4       !< *MAT_024 LCSS curve
  integer, parameter, public :: HARDENING_JOHNSON_COOK = 5 !< *MAT_015, *MAT_098

  !> Plastic strain below which the Johnson-Cook slope is taken at this strain (N < 1).
  real(wp), parameter :: JC_SLOPE_STRAIN = 1.0e-12_wp

  !> *MAT_018: SIGY below this value is the strain offset itself, not a stress.
  real(wp), parameter, public :: POWER_LAW_STRAIN_LIMIT = 0.02_wp

  public :: hardening_yield, hardening_yield_block, piecewise_linear_law
  public :: power_law_strain_offset, plastic_modulus, hardening_rate_factor,  &
            rate_dependent, rate_table_material, viscoplastic

  !> Curves of at most this many points have their segment found by counting (the block
  !> version); longer ones by bisection, point by point
  integer, parameter :: COUNTED_SEGMENT_POINTS = 16

contains

  !> The hardening law of a *MAT_024 material: LCSS curve first, then the EPS/ES table,
  !> else SIGY + ETAN (the precedence of LS-DYNA).
  pure integer function piecewise_linear_law(mat)
    type(material_t), intent(in) :: mat   !< a *MAT_PIECEWISE_LINEAR_PLASTICITY material
    if (mat%lcss_curve > 0) then
      piecewise_linear_law = HARDENING_CURVE
    else if (mat%n_points >= 2) then
      piecewise_linear_law = HARDENING_TABLE
    else
      piecewise_linear_law = HARDENING_LINEAR
    end if
  end function piecewise_linear_law

  !> Uniaxial yield stress K(alpha) and slope K'(alpha) of a hardening law.
  pure subroutine hardening_yield(law, mat, curves, alpha, yield_stress, slope)
    integer, intent(in) :: law                 !< HARDENING_*
    type(material_t), intent(in) :: mat        !< the material's parameters
    type(curve_t), intent(in) :: curves(:)     !< the model's curves (for LCSS)
    real(wp), intent(in) :: alpha              !< equivalent plastic strain (>= 0)
    real(wp), intent(out) :: yield_stress      !< K(alpha)
    real(wp), intent(out) :: slope             !< K'(alpha)
    real(wp) :: strain
    select case (law)
    case (HARDENING_POWER_LAW)
      if (mat%n_exponent == 0.0_wp) then
        yield_stress = mat%k_strength
        slope = 0.0_wp
      else
        strain = power_law_strain_offset(mat) + alpha
        yield_stress = mat%k_strength*strain**mat%n_exponent
        slope = mat%n_exponent*yield_stress/strain
      end if
    case (HARDENING_LINEAR)
      slope = plastic_modulus(mat)
      yield_stress = mat%yield_stress + slope*alpha
    case (HARDENING_TABLE)
      call piecewise_linear(mat%n_points, mat%eps, mat%es, alpha, yield_stress, slope)
    case (HARDENING_CURVE)
      associate (curve => curves(mat%lcss_curve))
        yield_stress = curve_value(curve, alpha)
        slope = segment_slope(curve%n, curve%t, curve%f, alpha)
      end associate
      if (mat%lcss_weight > 0.0_wp) then           ! a rate table: blend with the next curve
        associate (upper => curves(mat%lcss_upper))
          yield_stress = (1.0_wp - mat%lcss_weight)*yield_stress + &
                         mat%lcss_weight*curve_value(upper, alpha)
          slope = (1.0_wp - mat%lcss_weight)*slope + &
                  mat%lcss_weight*segment_slope(upper%n, upper%t, upper%f, alpha)
        end associate
      end if
    case (HARDENING_JOHNSON_COOK)
      if (mat%n_exponent == 0.0_wp) then
        yield_stress = mat%jc_a + mat%jc_b
        slope = 0.0_wp
      else
        yield_stress = mat%jc_a + mat%jc_b*alpha**mat%n_exponent
        slope = mat%n_exponent*mat%jc_b*max(alpha, JC_SLOPE_STRAIN)**(mat%n_exponent - 1.0_wp)
      end if
      if (mat%max_stress > 0.0_wp .and. yield_stress > mat%max_stress) then
        yield_stress = mat%max_stress
        slope = 0.0_wp
      end if
    case default
      yield_stress = 0.0_wp
      slope = 0.0_wp
    end select
    if (mat%vp_dt > 0.0_wp) call viscoplastic_scale(mat, curves, alpha, yield_stress, slope)
  end subroutine hardening_yield

  !> hardening_yield for n points at once (the same values, bit for bit): the linear law and
  !> the tables and short curves of the piecewise linear law without branches, so that the
  !> loop over the points is free of calls and mispredicted jumps; a table's or curve's
  !> segment is found by counting its interior abscissas at or below alpha, which is the
  !> segment of the bisection (abscissas increasing). The power law and long curves take
  !> hardening_yield point by point.
  pure subroutine hardening_yield_block(law, mat, curves, n, alpha, yield_stress, slope)
    integer, intent(in) :: law                 !< HARDENING_*
    type(material_t), intent(in) :: mat        !< the material's parameters
    type(curve_t), intent(in) :: curves(:)     !< the model's curves (for LCSS)
    integer, intent(in) :: n                   !< number of points
    real(wp), intent(in) :: alpha(:)           !< (>= n) equivalent plastic strains
    real(wp), intent(out) :: yield_stress(:)   !< (>= n) K(alpha)
    real(wp), intent(out) :: slope(:)          !< (>= n) K'(alpha)
    real(wp) :: modulus
    integer :: i, k, lo, points
    select case (law)
    case (HARDENING_LINEAR)
      modulus = plastic_modulus(mat)
      do i = 1, n
        slope(i) = modulus
        yield_stress(i) = mat%yield_stress + modulus*alpha(i)
      end do
      return
    case (HARDENING_TABLE)
      points = mat%n_points
      if (points >= 2) then                    ! (piecewise_linear's arithmetic)
        do i = 1, n
          lo = 1
          do k = 2, points - 1
            lo = lo + merge(1, 0, mat%eps(k) <= alpha(i))
          end do
          slope(i) = (mat%es(lo+1) - mat%es(lo))/(mat%eps(lo+1) - mat%eps(lo))
          yield_stress(i) = mat%es(lo) + slope(i)*(alpha(i) - mat%eps(lo))
        end do
        return
      end if
    case (HARDENING_CURVE)
      associate (curve => curves(mat%lcss_curve))
        points = curve%n
        if (points >= 2 .and. points <= COUNTED_SEGMENT_POINTS) then
          do i = 1, n                          ! (curve_value's and segment_slope's arithmetic)
            lo = 1
            do k = 2, points - 1
              lo = lo + merge(1, 0, curve%t(k) <= alpha(i))
            end do
            yield_stress(i) = curve%f(lo) + (curve%f(lo+1) - curve%f(lo))* &
                              (alpha(i) - curve%t(lo))/(curve%t(lo+1) - curve%t(lo))
            slope(i) = (curve%f(lo+1) - curve%f(lo))/(curve%t(lo+1) - curve%t(lo))
          end do
          return
        end if
      end associate
    end select
    do i = 1, n
      call hardening_yield(law, mat, curves, alpha(i), yield_stress(i), slope(i))
    end do
  end subroutine hardening_yield_block

  !> *MAT_018 strain offset eps_yp from SIGY, E, K and N (rule in the module header).
  !> With SIGY = 0 and N = 1 the lines do not meet; 0 is returned.
  pure real(wp) function power_law_strain_offset(mat)
    type(material_t), intent(in) :: mat   !< a *MAT_POWER_LAW_PLASTICITY material
    if (mat%yield_stress <= 0.0_wp) then
      if (mat%n_exponent == 1.0_wp) then
        power_law_strain_offset = 0.0_wp
      else
        power_law_strain_offset = (mat%young/mat%k_strength)**(1.0_wp/(mat%n_exponent - 1.0_wp))
      end if
    else if (mat%yield_stress < POWER_LAW_STRAIN_LIMIT) then
      power_law_strain_offset = mat%yield_stress
    else if (mat%n_exponent > 0.0_wp) then
      power_law_strain_offset = (mat%yield_stress/mat%k_strength)**(1.0_wp/mat%n_exponent)
    else
      power_law_strain_offset = 0.0_wp
    end if
  end function power_law_strain_offset

  !> True when the material's yield stress depends on the strain rate: an LCSR curve (*MAT_024),
  !> a Cowper-Symonds C (SRC) > 0, or a Johnson-Cook C /= 0; also a Johnson-Cook failure with
  !> D4 /= 0 (its failure strain depends on the rate).
  pure logical function rate_dependent(mat)
    type(material_t), intent(in) :: mat        !< the material's parameters
    rate_dependent = mat%lcss_table > 0 .or. mat%lcsr_curve > 0 .or. mat%cowper_c > 0.0_wp .or. &
                     ((mat%kind == MAT_JOHNSON_COOK .or. &
                       mat%kind == MAT_SIMPLIFIED_JOHNSON_COOK) .and. mat%jc_c /= 0.0_wp) .or. &
                     (mat%jc_fails .and. mat%jc_damage(4) /= 0.0_wp)
  end function rate_dependent

  !> Scale of the yield stress at the effective strain rate: Johnson-Cook 1 + C ln(rate/EPSO)
  !> above EPSO (*MAT_015, *MAT_098); the LCSR curve's value at the rate (*MAT_024), else
  !> Cowper-Symonds 1 + (rate/C)^(1/P), else 1.
  pure real(wp) function hardening_rate_factor(mat, curves, strain_rate) result(factor)
    type(material_t), intent(in) :: mat        !< the material's parameters
    type(curve_t), intent(in) :: curves(:)     !< the model's curves (for LCSR)
    real(wp), intent(in) :: strain_rate        !< effective strain rate (1/time, >= 0)
    factor = 1.0_wp
    if (mat%lcss_table > 0) return                 ! the table's curves hold the rate effect
    if (viscoplastic(mat)) return                  ! VP = 1: the plastic rate (viscoplastic_scale)
    if (mat%kind == MAT_JOHNSON_COOK .or. mat%kind == MAT_SIMPLIFIED_JOHNSON_COOK) then
      if (strain_rate > mat%reference_rate) factor = 1.0_wp + &
          mat%jc_c*log(strain_rate/mat%reference_rate)
    else if (mat%lcsr_curve > 0) then
      factor = curve_value(curves(mat%lcsr_curve), strain_rate)
    else if (mat%cowper_c > 0.0_wp .and. strain_rate > 0.0_wp) then
      factor = 1.0_wp + (strain_rate/mat%cowper_c)**(1.0_wp/mat%cowper_p)
    end if
  end function hardening_rate_factor

  !> *MAT_024 plastic modulus Ep = E ETAN/(E - ETAN) (0 for ETAN = 0).
  pure real(wp) function plastic_modulus(mat)
    type(material_t), intent(in) :: mat   !< a *MAT_PIECEWISE_LINEAR_PLASTICITY material
    plastic_modulus = mat%young*mat%tangent_modulus/(mat%young - mat%tangent_modulus)
  end function plastic_modulus

  !> Value and slope of the piecewise linear function through (x(i), y(i)), i = 1..n,
  !> extended linearly outside [x(1), x(n)].
  pure subroutine piecewise_linear(n, x, y, t, value, slope)
    integer, intent(in) :: n               !< number of points (>= 1)
    real(wp), intent(in) :: x(:), y(:)     !< abscissas (increasing) and ordinates
    real(wp), intent(in) :: t              !< where to evaluate
    real(wp), intent(out) :: value         !< the function's value
    real(wp), intent(out) :: slope         !< its slope
    integer :: lo
    if (n == 1) then
      value = y(1)
      slope = 0.0_wp
      return
    end if
    lo = segment(n, x, t)
    slope = (y(lo+1) - y(lo))/(x(lo+1) - x(lo))
    value = y(lo) + slope*(t - x(lo))
  end subroutine piecewise_linear

  !> Slope of the segment of a piecewise linear function used at t (0 for one point).
  pure real(wp) function segment_slope(n, x, y, t)
    integer, intent(in) :: n               !< number of points
    real(wp), intent(in) :: x(:), y(:)     !< abscissas (increasing) and ordinates
    real(wp), intent(in) :: t              !< where to evaluate
    integer :: lo
    if (n <= 1) then
      segment_slope = 0.0_wp
      return
    end if
    lo = segment(n, x, t)
    segment_slope = (y(lo+1) - y(lo))/(x(lo+1) - x(lo))
  end function segment_slope

  !> First point lo of the segment [x(lo), x(lo+1)] used at t, chosen as curve_value of
  !> mefem_curves does: the first/last segment outside the range, else x(lo) <= t < x(lo+1).
  pure integer function segment(n, x, t)
    integer, intent(in) :: n               !< number of points (>= 2)
    real(wp), intent(in) :: x(:)           !< abscissas (increasing)
    real(wp), intent(in) :: t              !< where to evaluate
    integer :: hi, mid
    if (t <= x(1)) then
      segment = 1
    else if (t >= x(n)) then
      segment = n - 1
    else
      segment = 1
      hi = n
      do while (hi - segment > 1)
        mid = (segment + hi)/2
        if (x(mid) <= t) then
          segment = mid
        else
          hi = mid
        end if
      end do
    end if
  end function segment

  !> *MAT_024 with VP = 1 (viscoplastic, as LS-DYNA defines it): within one update the yield
  !> stress is K(alpha) R(rate_p), the rate factor (Cowper-Symonds 1 + (rate_p/C)^(1/P), or
  !> the LCSR curve) of the plastic strain rate rate_p = (alpha - alpha_n)/dt of the step
  !> (mat%vp_alpha_old, mat%vp_dt); the slope K' R + K R'/dt. R' of Cowper-Symonds is infinite
  !> at rate_p = 0 (P > 1): it is taken at VP_RATE_FLOOR C there (the return map's bisection
  !> guards its Newton steps).
  pure subroutine viscoplastic_scale(mat, curves, alpha, yield_stress, slope)
    type(material_t), intent(in) :: mat        !< *MAT_024 with vp_dt > 0
    type(curve_t), intent(in) :: curves(:)     !< the model's curves (LCSR)
    real(wp), intent(in) :: alpha              !< equivalent plastic strain
    real(wp), intent(inout) :: yield_stress    !< K(alpha) -> K R
    real(wp), intent(inout) :: slope           !< K'(alpha) -> d(K R)/d alpha
    !> fraction of C at which the Cowper-Symonds slope is taken at rate 0
    real(wp), parameter :: VP_RATE_FLOOR = 1.0e-12_wp
    real(wp) :: rate, factor, factor_slope
    rate = max(alpha - mat%vp_alpha_old, 0.0_wp)/mat%vp_dt
    if (mat%lcsr_curve > 0) then
      associate (curve => curves(mat%lcsr_curve))
        factor = curve_value(curve, rate)
        factor_slope = segment_slope(curve%n, curve%t, curve%f, rate)
      end associate
    else
      factor = 1.0_wp + (rate/mat%cowper_c)**(1.0_wp/mat%cowper_p)
      factor_slope = (max(rate, VP_RATE_FLOOR*mat%cowper_c)/mat%cowper_c)** &
                     (1.0_wp/mat%cowper_p - 1.0_wp)/(mat%cowper_p*mat%cowper_c)
    end if
    slope = slope*factor + yield_stress*factor_slope/mat%vp_dt
    yield_stress = yield_stress*factor
  end subroutine viscoplastic_scale

  !> *MAT_024 (C, P or LCSR; not an LCSS table), *MAT_018 or *MAT_003 (SRC, SRP) with VP = 1:
  !> its yield stress follows the plastic strain rate (viscoplastic_scale; *MAT_003: its own
  !> return, kinematic_viscoplastic_dgamma), not the total rate.
  pure logical function viscoplastic(mat)
    type(material_t), intent(in) :: mat        !< the material's parameters
    viscoplastic = (mat%kind == MAT_PIECEWISE_LINEAR .or. mat%kind == MAT_POWER_LAW .or. &
                    mat%kind == MAT_PLASTIC_KINEMATIC) .and. mat%vp == 1.0_wp .and. &
                   mat%lcss_table == 0 .and. (mat%cowper_c > 0.0_wp .or. mat%lcsr_curve > 0)
  end function viscoplastic

  !> *MAT_024 with an LCSS table: the material with the curves around the strain rate set for
  !> one update: lcss_curve the table's curve at or below the rate (ln of the rate when the
  !> table's values are logarithms), lcss_upper the next, lcss_weight the linear weight of the
  !> upper in the rate (or ln rate); rates outside the table take its first or last curve.
  pure function rate_table_material(mat, curves, strain_rate) result(local)
    type(material_t), intent(in) :: mat        !< *MAT_024 with lcss_table > 0
    type(curve_t), intent(in) :: curves(:)     !< the model's curves and tables
    real(wp), intent(in) :: strain_rate        !< effective strain rate (1/time, >= 0)
    type(material_t) :: local
    real(wp) :: x
    integer :: lo
    local = mat
    associate (table => curves(mat%lcss_table))
      local%lcss_weight = 0.0_wp
      if (mat%lcss_log_rates) then
        if (.not. strain_rate > 0.0_wp) then
          local%lcss_curve = table%members(1)
          return
        end if
        x = log(strain_rate)
      else
        x = strain_rate
      end if
      if (x <= table%t(1)) then
        local%lcss_curve = table%members(1)
      else if (x >= table%t(table%n)) then
        local%lcss_curve = table%members(table%n)
      else
        lo = segment(table%n, table%t, x)
        local%lcss_curve = table%members(lo)
        local%lcss_upper = table%members(lo + 1)
        local%lcss_weight = (x - table%t(lo))/(table%t(lo + 1) - table%t(lo))
      end if
    end associate
  end function rate_table_material

end module mefem_hardening
