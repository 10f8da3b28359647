!> *MAT_PLASTIC_KINEMATIC (MAT_003, mat_j2_kinematic_update) driven along deformation paths:
!> 1 BETA = 1 is the isotropic bilinear law of *MAT_024 (SIGY, ETAN): the same stresses;
!> 2 isochoric uniaxial tension, then reversed: the reverse yield (Bauschinger) sits 2 SIGY
!>   below the largest stress for BETA = 0 (kinematic), 2 x the largest stress for BETA = 1, and
!>   2 (SIGY + BETA Ep alpha) in between (BETA = 0.5); the hardening slopes;
!> 3 objectivity with a back stress: tau(R F) = R tau(F) R^T after a plastic path;
!> 4 the tangent against central differences along non-symmetric directions h (spin
!>   included: the back stress's rotation), and a rotation gives D tau = h tau + tau h^T.
program test_plastic_kinematic
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_errors, only: status_t
  use mefem_strings, only: rtoa
  use mefem_model, only: material_t, curve_t, MAT_PIECEWISE_LINEAR, MAT_PLASTIC_KINEMATIC
  use mefem_material_state, only: NHIST, HIST_ALPHA, HIST_BACK, material_state_init
  use mefem_material_update, only: material_update
  implicit none

  real(wp), parameter :: YOUNG = 200000.0_wp, POISSON = 0.3_wp, SIGY = 200.0_wp
  real(wp), parameter :: ETAN = 20000.0_wp          !< Ep = E ETAN/(E - ETAN) = E/9
  type(curve_t), allocatable :: curves(:)

  allocate(curves(0))
  call test_start('plastic_kinematic')
  call test_isotropic_limit()
  call test_bauschinger(0.0_wp)
  call test_bauschinger(0.5_wp)
  call test_bauschinger(1.0_wp)
  call test_objectivity()
  call test_tangent()
  call test_finish()

contains

  !> A *MAT_003 card (or *MAT_024 with SIGY and ETAN) of steel-like constants.
  type(material_t) function steel(kind, beta) result(mat)
    integer, intent(in) :: kind             !< MAT_PLASTIC_KINEMATIC or MAT_PIECEWISE_LINEAR
    real(wp), intent(in) :: beta            !< BETA
    mat%id = 3
    mat%kind = kind
    mat%density = 7.85e-9_wp
    mat%young = YOUNG
    mat%poisson = POISSON
    mat%yield_stress = SIGY
    mat%tangent_modulus = ETAN
    mat%beta = beta
  end function steel

  !> Isochoric uniaxial stretch along x: F = diag(l, l^-1/2, l^-1/2).
  function uniaxial(l) result(f)
    real(wp), intent(in) :: l
    real(wp) :: f(3, 3)
    f = 0.0_wp
    f(1, 1) = l
    f(2, 2) = 1.0_wp/sqrt(l)
    f(3, 3) = 1.0_wp/sqrt(l)
  end function uniaxial

  !> One update; a failure is reported (as a failed check).
  subroutine step(mat, f, hist, tau)
    type(material_t), intent(in) :: mat
    real(wp), intent(in) :: f(3, 3)
    real(wp), intent(inout) :: hist(NHIST)
    real(wp), intent(out) :: tau(3, 3)
    real(wp) :: hist_new(NHIST), sound
    type(status_t) :: status
    call material_update(mat, curves, f, hist, hist_new, tau, sound_speed=sound, status=status)
    if (.not. status%ok) call check(.false., 'update succeeds', status%message)
    hist = hist_new
  end subroutine step

  !> BETA = 1 against *MAT_024 with the same SIGY and ETAN along tension and reversal.
  subroutine test_isotropic_limit()
    real(wp) :: h3(NHIST), h24(NHIST), tau3(3, 3), tau24(3, 3), worst, l
    integer :: k
    call material_state_init(h3)
    call material_state_init(h24)
    worst = 0.0_wp
    do k = 1, 60
      l = exp(0.0004_wp*real(min(k, 80 - k), wp))     ! to 0.8 % strain and back to 0.8 %
      call step(steel(MAT_PLASTIC_KINEMATIC, 1.0_wp), uniaxial(l), h3, tau3)
      call step(steel(MAT_PIECEWISE_LINEAR, 0.0_wp), uniaxial(l), h24, tau24)
      worst = max(worst, maxval(abs(tau3 - tau24)))
    end do
    call check(worst <= 1e-9_wp*SIGY, 'BETA = 1 is *MAT_024 with SIGY, ETAN', rtoa(worst))
    call check(h3(HIST_ALPHA) > 0.0_wp .and. abs(h3(HIST_ALPHA) - h24(HIST_ALPHA)) < 1e-12_wp, &
               'BETA = 1: the same plastic strain')
  end subroutine test_isotropic_limit

  !> Tension to 1 % log strain, then compression: the axial-lateral stress difference s(e).
  !> Reverse yield where the slope first drops below half the elastic 3 mu; expected at
  !> s_max - 2 (SIGY + BETA Ep alpha_max) (small strains: the tolerance is the strain step's
  !> stress change plus 1 % for the finite strain).
  subroutine test_bauschinger(beta)
    real(wp), intent(in) :: beta
    real(wp), parameter :: DE = 1.0e-5_wp
    real(wp) :: hist(NHIST), tau(3, 3), s, s_previous, s_max, alpha_max, ep, mu, e, reverse
    real(wp) :: expected, slope_elastic, back_norm
    integer :: k, n_up
    character(len=8) :: label
    write (label, '(f3.1)') beta
    mu = YOUNG/(2.0_wp*(1.0_wp + POISSON))
    ep = YOUNG*ETAN/(YOUNG - ETAN)
    slope_elastic = 3.0_wp*mu
    call material_state_init(hist)
    n_up = 1000
    s = 0.0_wp
    do k = 1, n_up                                  ! tension to 1 %
      call step(steel(MAT_PLASTIC_KINEMATIC, beta), uniaxial(exp(DE*k)), hist, tau)
    end do
    s_max = tau(1, 1) - tau(2, 2)
    alpha_max = hist(HIST_ALPHA)
    ! the stress at the top: SIGY + Ep alpha (isotropic and kinematic parts together)
    call check_close(s_max, SIGY + ep*alpha_max, 0.01_wp, 'BETA '//trim(label)// &
                     ': stress at 1 % = SIGY + Ep alpha')
    back_norm = sqrt(sum(hist(HIST_BACK:HIST_BACK + 2)**2) + &
                     2.0_wp*sum(hist(HIST_BACK + 3:HIST_BACK + 5)**2))
    if (beta < 1.0_wp) then
      call check_close(back_norm, sqrt(2.0_wp/3.0_wp)*(1.0_wp - beta)*ep*alpha_max, 0.01_wp, &
                       'BETA '//trim(label)//': back stress |b| = sqrt(2/3) (1 - BETA) Ep alpha')
    else
      call check(back_norm == 0.0_wp, 'BETA 1.0: no back stress')
    end if
    reverse = huge(1.0_wp)
    s_previous = s_max
    do k = n_up - 1, -n_up, -1                      ! back, and on into compression
      e = DE*k
      call step(steel(MAT_PLASTIC_KINEMATIC, beta), uniaxial(exp(e)), hist, tau)
      s = tau(1, 1) - tau(2, 2)
      if ((s_previous - s)/DE < 0.5_wp*slope_elastic) then
        reverse = s_previous
        exit
      end if
      s_previous = s
    end do
    expected = s_max - 2.0_wp*(SIGY + beta*ep*alpha_max)
    write (*, '(a, f4.1, 3(a, f9.3))') '    BETA', beta, ': s_max ', s_max, ' MPa, reverse '// &
        'yield ', reverse, ' MPa, expected ', expected
    call check(abs(reverse - expected) <= slope_elastic*DE + 0.01_wp*abs(expected), &
               'BETA '//trim(label)//': reverse yield at s_max - 2 (SIGY + BETA Ep alpha)', &
               'got '//rtoa(reverse)//', expected '//rtoa(expected))
  end subroutine test_bauschinger

  !> Rotation R(theta) about the axis (1, 2, 3)/sqrt(14).
  function rotation(theta) result(r)
    real(wp), intent(in) :: theta
    real(wp) :: r(3, 3), n(3), k(3, 3)
    integer :: i
    n = [1.0_wp, 2.0_wp, 3.0_wp]/sqrt(14.0_wp)
    k = reshape([0.0_wp, n(3), -n(2), -n(3), 0.0_wp, n(1), n(2), -n(1), 0.0_wp], [3, 3])
    r = sin(theta)*k + (1.0_wp - cos(theta))*matmul(k, k)
    do i = 1, 3
      r(i, i) = r(i, i) + 1.0_wp
    end do
  end function rotation

  !> A plastic path (tension, shear, partial reversal) leaves a back stress; a superposed
  !> rotation of the last step rotates the stress: tau(R F) = R tau(F) R^T, with a history
  !> built along the same path rotated by R(t) (a rotating body).
  subroutine test_objectivity()
    real(wp) :: h_plain(NHIST), h_rotating(NHIST), tau(3, 3), tau_r(3, 3), f(3, 3), r(3, 3)
    real(wp) :: worst, t
    integer :: k
    call material_state_init(h_plain)
    call material_state_init(h_rotating)
    worst = 0.0_wp
    do k = 1, 60
      t = real(k, wp)/60.0_wp
      f = uniaxial(exp(0.006_wp*sin(3.0_wp*t)))
      f(1, 2) = 0.01_wp*t
      r = rotation(2.0_wp*t)
      call step(steel(MAT_PLASTIC_KINEMATIC, 0.3_wp), f, h_plain, tau)
      call step(steel(MAT_PLASTIC_KINEMATIC, 0.3_wp), matmul(r, f), h_rotating, tau_r)
      worst = max(worst, maxval(abs(tau_r - matmul(r, matmul(tau, transpose(r))))))
    end do
    call check(maxval(abs(h_plain(HIST_BACK:HIST_BACK + 5))) > 1.0_wp, 'objectivity: the '// &
               'path leaves a back stress')
    call check(worst <= 1e-9_wp*SIGY, 'objectivity: tau(R F) = R tau(F) R^T along the path', &
               rtoa(worst))
  end subroutine test_objectivity

  !> c : sym(h) + h tau + tau h^T against central differences of tau(F + e h F) for general h
  !> (plastic step, back stress present); a pure spin h gives h tau + tau h^T.
  subroutine test_tangent()
    real(wp) :: hist(NHIST), hist_new(NHIST), tau(3, 3), c(3, 3, 3, 3), f(3, 3), h(3, 3)
    real(wp) :: tp(3, 3), tm(3, 3), predicted(3, 3), fd(3, 3), worst, scale_c, sound
    real(wp), parameter :: E = 1.0e-7_wp
    type(status_t) :: status
    integer :: k, m
    call material_state_init(hist)
    do k = 1, 40                                      ! plastic tension, then shear
      f = uniaxial(exp(0.0002_wp*k))
      f(1, 3) = 0.0001_wp*k
      call step(steel(MAT_PLASTIC_KINEMATIC, 0.5_wp), f, hist, tau)
    end do
    f = uniaxial(exp(0.0082_wp))
    f(1, 3) = 0.0041_wp
    call material_update(steel(MAT_PLASTIC_KINEMATIC, 0.5_wp), curves, f, hist, hist_new, tau, &
                         c, sound, status)
    call check(hist_new(HIST_ALPHA) > hist(HIST_ALPHA), 'tangent: a plastic step')
    scale_c = maxval(abs(c))
    worst = 0.0_wp
    do m = 1, 3
      h = reshape([0.3_wp, -0.2_wp, 0.5_wp, 0.1_wp, 0.4_wp, -0.7_wp, 0.6_wp, 0.2_wp, -0.1_wp], &
                  [3, 3])
      if (m == 2) h = transpose(h)
      if (m == 3) h = h - transpose(h)                 ! a pure spin
      call material_update(steel(MAT_PLASTIC_KINEMATIC, 0.5_wp), curves, f + E*matmul(h, f), &
                           hist, hist_new, tp, sound_speed=sound, status=status)
      call material_update(steel(MAT_PLASTIC_KINEMATIC, 0.5_wp), curves, f - E*matmul(h, f), &
                           hist, hist_new, tm, sound_speed=sound, status=status)
      fd = (tp - tm)/(2.0_wp*E)
      predicted = matmul(h, tau) + matmul(tau, transpose(h)) + &
                  contract(c, 0.5_wp*(h + transpose(h)))
      worst = max(worst, maxval(abs(fd - predicted))/scale_c)
    end do
    call check(worst < 1e-5_wp, 'tangent: c : sym(h) + h tau + tau h^T = D tau[h F] (spin '// &
               'included)', rtoa(worst))
  end subroutine test_tangent

  !> c : a for a 3x3 a.
  function contract(c, a) result(b)
    real(wp), intent(in) :: c(3, 3, 3, 3), a(3, 3)
    real(wp) :: b(3, 3)
    integer :: i, j
    do j = 1, 3
      do i = 1, 3
        b(i, j) = sum(c(i, j, :, :)*a)
      end do
    end do
  end function contract

end program test_plastic_kinematic
