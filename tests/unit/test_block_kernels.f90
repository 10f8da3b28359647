!> Block kernels of the explicit cell loop (structure of arrays, BLOCK_POINTS cells at a time)
!> against the point kernels they restate, on random cells:
!> - block_deformation_gradient, block_adjugate, block_internal_force: the same bits as
!>   cell_deformation_gradient, the determinant of mat_j2_update's det3 and
!>   cell_internal_force (7- and 5-node cells);
!> - mat_j2_update_block (through material_update_block): the same bits as mat_j2_update for
!>   elastic and plastic steps of the three hardening laws of *MAT_024/*MAT_018 from a
!>   plastically deformed history; an inverted cell is reported (ok = .false.) with its
!>   history untouched while its neighbours in the block are updated;
!> - mat_j2_kinematic_update_block (*MAT_003, BETA = 0.3, through material_update_block): the
!>   same bits as mat_j2_kinematic_update from a plastic history (its block polar rotation
!>   the point iteration's), and the same bits at every place in blocks of 1 to BLOCK_POINTS;
!> - mat_elastic_update_block (through material_update_block): the same bits as
!>   mat_elastic_update at strains of 1e-2 and 0.3, at any place in blocks of 1 to
!>   BLOCK_POINTS points, an inverted point reported;
!> - block_critical_omega_squared: within 1e-13 of cell_critical_omega_squared (the
!>   trigonometric step of the eigenvalue is a Chebyshev series there), equal for an isotropic
!>   metric (double eigenvalue: the series' end point), huge for det F <= 0;
!> - placement: a cell gives the same bits whatever its place in a block and the block's
!>   length (odd lengths exercise the vector loops' scalar remainders): what keeps results
!>   bit-identical across rank counts; J2 points with |J - 1| beyond the cube root's series
!>   range too (its pow must not be libmvec's vector pow).
!> The comparisons with the point kernels hold in the debug build (make test's): with the
!> release flags gfortran contracts a*b + c differently in vector loops and scalar routines.
!> The placement checks are the release build's concern (vectorisation): with the argument
!> `placement` only they run, and make test runs them so on the release build as well.
program test_block_kernels
  use mefem_kinds, only: wp
  use mefem_tensor_algebra, only: IDENTITY
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_errors, only: status_t
  use mefem_model, only: material_t, curve_t, MAT_PLASTIC_KINEMATIC
  use mefem_cells, only: CELL_MAX_NODES
  use mefem_material_state, only: NHIST, HIST_ALPHA, BLOCK_POINTS, material_state_init
  use mefem_material_update, only: material_update, material_update_block
  use mefem_cell_finite_strain, only: cell_deformation_gradient, cell_internal_force, &
                                      block_deformation_gradient, block_adjugate, &
                                      block_internal_force, block_face_deformation_gradient, &
                                      block_face_internal_force, face_gradients_expanded, &
                                      FACE_COMPACT_COLUMNS
  use mefem_stable_time_step, only: cell_critical_omega_squared, block_critical_omega_squared, &
                                    METRIC_ENTRIES, metric_packed, metric_unpacked, &
                                    cell_reference_bound, block_quick_omega_squared
  use mefem_test_fixtures, only: linear_steel, table_steel, power_law_steel, elastic_steel
  implicit none

  integer, parameter :: LD = BLOCK_POINTS
  integer, parameter :: NCELL = 29                  !< odd: vector loops end with a remainder
  real(wp), parameter :: LAMBDA = 1.1e5_wp, MU = 8.0e4_wp   !< Lame constants (MPa)
  !> scale of the random displacement gradients: elastic steps (1e-4) and plastic ones (1e-2)
  real(wp), parameter :: ELASTIC_STRAIN = 1.0e-4_wp, PLASTIC_STRAIN = 1.0e-2_wp
  type(curve_t), allocatable :: curves(:)
  logical :: placement_only                         !< argument `placement`: those checks only
  character(len=16) :: argument

  call test_start('block_kernels')
  allocate(curves(0))
  call get_command_argument(1, argument)
  placement_only = argument == 'placement'
  if (.not. placement_only) then
    call check_element_kernels(7)
    call check_element_kernels(5)
    call check_face_kernels(7)
    call check_face_kernels(5)
    call check_material(linear_steel(), 'linear hardening')
    call check_material(table_steel(), 'EPS/ES table')
    call check_material(power_law_steel(), 'power law')
    call check_material(fine_table_steel(), 'EPS/ES table 0.002 apart')
    call check_material(kinematic_steel(), 'MAT_003 BETA 0.3')
    call check_failed_point()
    call check_stable_step()
  end if
  call check_elastic()
  call check_large_volume_change()
  call check_kinematic_placement()
  call check_placement(.false.)
  call check_placement(.true.)
  call test_finish()

contains

  !> The face kernels (compact gradients, mefem_cell_finite_strain) against the point kernels
  !> on the expanded gradients, for NCELL random cells of nn nodes (7, or 5: a boundary cell,
  !> slots 6 and 7 with zero displacements): F and the forces to round-off (their sums are
  !> arranged differently, so not the same bits).
  subroutine check_face_kernels(nn)
    integer, intent(in) :: nn              !< nodes of the cells
    real(wp) :: u(LD, 3, 7), compact(LD, 3, FACE_COMPACT_COLUMNS), f(LD, 9), adj(LD, 9)
    real(wp) :: det(LD), tau(LD, 6), weight(LD), force(LD, 3, 7), grad(3, 7)
    real(wp) :: f_point(3, 3), tau_point(3, 3), force_point(3, 7), f_error, force_error
    integer :: i
    call random_number(u)
    u = 0.05_wp*(u - 0.5_wp)
    if (nn == 5) u(:, :, 6:7) = 0.0_wp
    call random_number(compact)
    compact = compact - 0.5_wp
    call random_number(weight)
    call random_number(tau)
    tau = 100.0_wp*(tau - 0.5_wp)
    call block_face_deformation_gradient(NCELL, u, compact, f)
    call block_adjugate(NCELL, f, adj, det)
    call block_face_internal_force(NCELL, compact, weight, adj, det, tau, force)
    f_error = 0.0_wp
    force_error = 0.0_wp
    do i = 1, NCELL
      grad = face_gradients_expanded(nn, compact(i, :, :))
      call cell_deformation_gradient(3, nn, grad(:, 1:nn), u(i, :, 1:nn), f_point)
      f_error = max(f_error, maxval(abs(reshape(f_point, [9]) - f(i, :))))
      tau_point = reshape([tau(i, 1), tau(i, 4), tau(i, 6), tau(i, 4), tau(i, 2), tau(i, 5), &
                           tau(i, 6), tau(i, 5), tau(i, 3)], [3, 3])
      call cell_internal_force(3, nn, grad(:, 1:nn), weight(i), reshape(f(i, :), [3, 3]), &
                               tau_point, force_point(:, 1:nn))
      force_error = max(force_error, maxval(abs(force_point(:, 1:nn) - force(i, :, 1:nn)))/ &
                                     maxval(abs(force_point(:, 1:nn))))
    end do
    call check(f_error <= 1.0e-15_wp, 'face kernels, '//trim(str(nn))//' nodes: F to '// &
               '1e-15 of the 7-slot sum (worst '//trim(rstr(f_error))//')')
    call check(force_error <= 1.0e-14_wp, 'face kernels, '//trim(str(nn))//' nodes: forces '// &
               'to 1e-14 of the largest (worst '//trim(rstr(force_error))//')')
  end subroutine check_face_kernels

  !> A random deformation gradient I + scale (R - 1/2), R uniform in [0, 1)^(3x3).
  subroutine random_f(scale, f)
    real(wp), intent(in) :: scale          !< size of the displacement gradient
    real(wp), intent(out) :: f(3, 3)       !< deformation gradient
    integer :: k
    call random_number(f)
    f = scale*(f - 0.5_wp)
    do k = 1, 3
      f(k, k) = f(k, k) + 1.0_wp
    end do
  end subroutine random_f

  !> F, J and the forces of NCELL random cells of nn nodes: block kernels vs point kernels.
  subroutine check_element_kernels(nn)
    integer, intent(in) :: nn              !< nodes per cell
    real(wp) :: u(LD, 3, CELL_MAX_NODES), grad(LD, 3, CELL_MAX_NODES), f(LD, 9), adj(LD, 9)
    real(wp) :: det(LD), tau(LD, 6), weight(LD), force(LD, 3, CELL_MAX_NODES)
    real(wp) :: f_point(3, 3), tau_point(3, 3), force_point(3, CELL_MAX_NODES), det3
    logical :: same_f, same_det, same_force
    integer :: i
    call random_number(u)
    u = 0.05_wp*(u - 0.5_wp)
    call random_number(grad)
    grad = grad - 0.5_wp
    call random_number(weight)
    call random_number(tau)
    tau = 100.0_wp*(tau - 0.5_wp)
    call block_deformation_gradient(NCELL, nn, u, grad, f)
    call block_adjugate(NCELL, f, adj, det)
    call block_internal_force(NCELL, nn, grad, weight, adj, det, tau, force)
    same_f = .true.
    same_det = .true.
    same_force = .true.
    do i = 1, NCELL
      call cell_deformation_gradient(3, nn, grad(i, :, 1:nn), u(i, :, 1:nn), f_point)
      same_f = same_f .and. all(reshape(f_point, [9]) == f(i, :))
      det3 = f_point(1, 1)*(f_point(2, 2)*f_point(3, 3) - f_point(2, 3)*f_point(3, 2)) &
           - f_point(1, 2)*(f_point(2, 1)*f_point(3, 3) - f_point(2, 3)*f_point(3, 1)) &
           + f_point(1, 3)*(f_point(2, 1)*f_point(3, 2) - f_point(2, 2)*f_point(3, 1))
      same_det = same_det .and. det3 == det(i)
      tau_point = reshape([tau(i, 1), tau(i, 4), tau(i, 6), tau(i, 4), tau(i, 2), tau(i, 5), &
                           tau(i, 6), tau(i, 5), tau(i, 3)], [3, 3])
      call cell_internal_force(3, nn, grad(i, :, 1:nn), weight(i), f_point, tau_point, &
                               force_point(:, 1:nn))
      same_force = same_force .and. all(force_point(:, 1:nn) == force(i, :, 1:nn))
    end do
    call check(same_f, 'F of '//trim(str(nn))//'-node cells: same bits as the point kernel')
    call check(same_det, 'J of '//trim(str(nn))//'-node cells: same bits as det3')
    call check(same_force, 'forces of '//trim(str(nn))//'-node cells: same bits as the point '// &
               'kernel')
  end subroutine check_element_kernels

  !> Histories of NCELL points after a few plastic steps (point kernel), then one block step
  !> with small (elastic) and large (plastic) increments: the same bits as the point kernel.
  subroutine check_material(mat, label)
    type(material_t), intent(in) :: mat    !< the J2 material
    character(len=*), intent(in) :: label  !< its name in the messages
    real(wp) :: hist(LD, NHIST), hist_point(NHIST, NCELL), hist_new(NHIST), f_point(3, 3)
    real(wp) :: f_total(3, 3, NCELL)       ! each point's deformation gradient so far
    real(wp) :: f(LD, 9), det(LD), tau(LD, 6), adj(LD, 9), tau_point(3, 3), sound
    logical :: ok(LD), same_hist, same_tau, all_ok
    type(status_t) :: status
    integer :: i, step, nplastic
    real(wp) :: scale
    do i = 1, NCELL                        ! a plastic history, point by point
      call material_state_init(hist_point(:, i))
      f_total(:, :, i) = IDENTITY
      do step = 1, 3
        call random_f(PLASTIC_STRAIN, f_point)
        f_point = matmul(f_point, f_total(:, :, i))
        call material_update(mat, curves, f_point, hist_point(:, i), hist_new, tau_point, &
                             sound_speed=sound, status=status)
        hist_point(:, i) = hist_new
        f_total(:, :, i) = f_point
      end do
    end do
    do step = 1, 2
      scale = merge(ELASTIC_STRAIN, PLASTIC_STRAIN, step == 1)
      do i = 1, NCELL
        call random_f(scale, f_point)
        f_point = matmul(f_point, f_total(:, :, i))
        f(i, :) = reshape(f_point, [9])
        hist(i, :) = hist_point(:, i)
      end do
      call block_adjugate(NCELL, f, adj, det)
      call material_update_block(mat, curves, NCELL, f, det, hist, tau, ok)
      same_hist = .true.
      same_tau = .true.
      all_ok = all(ok(1:NCELL))
      nplastic = 0
      do i = 1, NCELL
        f_point = reshape(f(i, :), [3, 3])
        call material_update(mat, curves, f_point, hist_point(:, i), hist_new, tau_point, &
                             sound_speed=sound, status=status)
        all_ok = all_ok .and. status%ok
        if (hist_new(HIST_ALPHA) > hist_point(HIST_ALPHA, i)) nplastic = nplastic + 1
        same_hist = same_hist .and. all(hist_new == hist(i, :))
        same_tau = same_tau .and. all([tau_point(1, 1), tau_point(2, 2), tau_point(3, 3), &
                                       tau_point(1, 2), tau_point(2, 3), tau_point(3, 1)] == &
                                      tau(i, :))
        hist_point(:, i) = hist_new
        f_total(:, :, i) = f_point
      end do
      call check(all_ok, label//', '//trim(merge('elastic', 'plastic', step == 1))// &
                 ' step: every point updated')
      call check((step == 1 .and. nplastic < NCELL) .or. (step == 2 .and. nplastic > 0), &
                 label//', '//trim(merge('elastic', 'plastic', step == 1))//' step: '// &
                 trim(str(nplastic))//' of '//trim(str(NCELL))//' points yield (both kinds '// &
                 'of step are exercised)')
      call check(same_hist, label//', '//trim(merge('elastic', 'plastic', step == 1))// &
                 ' step: histories bit-identical to mat_j2_update')
      call check(same_tau, label//', '//trim(merge('elastic', 'plastic', step == 1))// &
                 ' step: stresses bit-identical to mat_j2_update')
    end do
  end subroutine check_material

  !> *MAT_ELASTIC: the block kernel against mat_elastic_update, point by point at two strain
  !> scales, the points at every place of blocks of every length, and an inverted point.
  subroutine check_elastic()
    type(material_t) :: mat
    real(wp) :: f_all(3, 3, LD), f(LD, 9), adj(LD, 9), det(LD), tau(LD, 6), hist(LD, NHIST)
    real(wp) :: hist_new(NHIST), tau_point(3, 3), sound, want(6, LD), alone(6, LD), scale
    logical :: ok(LD), same, placed, all_ok
    type(status_t) :: status
    integer :: i, step
    mat = elastic_steel()
    do step = 1, 2
      scale = merge(PLASTIC_STRAIN, 0.3_wp, step == 1)
      do i = 1, LD
        call random_f(scale, f_all(:, :, i))
        call material_state_init(hist(i, :))
        call material_update(mat, curves, f_all(:, :, i), hist(i, :), hist_new, tau_point, &
                             sound_speed=sound, status=status)
        want(:, i) = [tau_point(1, 1), tau_point(2, 2), tau_point(3, 3), tau_point(1, 2), &
                      tau_point(2, 3), tau_point(3, 1)]
      end do
      call place_points(mat, f_all, alone, all_ok, placed)
      same = all(alone == want)
      if (.not. placement_only) call check(same, 'elastic block kernel, strain '// &
                                           trim(rtext(scale))//': the bits of mat_elastic_update')
      call check(all_ok .and. placed, 'elastic block kernel, strain '//trim(rtext(scale))// &
                 ': every point the same bits at every place in blocks of 1 to '//trim(str(LD)))
    end do
    f(1, :) = reshape(f_all(:, :, 1), [9])
    f(2, :) = [-1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp]
    call block_adjugate(2, f, adj, det)
    call material_update_block(mat, curves, 2, f, det, hist, tau, ok)
    call check(ok(1) .and. .not. ok(2) .and. all(tau(2, :) == 0.0_wp), &
               'elastic block kernel: an inverted point is reported, with no stress')
  end subroutine check_elastic

  !> J2 points with |J - 1| beyond the cube root's series range (the block's scalar loop):
  !> every point the same bits at every place in blocks of 1 to BLOCK_POINTS points.
  subroutine check_large_volume_change()
    real(wp) :: f_all(3, 3, LD), alone(6, LD), stretch
    logical :: placed, all_ok
    integer :: i
    do i = 1, LD                          ! J from 0.6 to 1.5 (range 0.1)
      call random_f(PLASTIC_STRAIN, f_all(:, :, i))
      stretch = (0.6_wp + 0.9_wp*real(i - 1, wp)/real(LD - 1, wp))**(1.0_wp/3.0_wp)
      f_all(:, :, i) = stretch*f_all(:, :, i)
    end do
    call place_points(linear_steel(), f_all, alone, all_ok, placed)
    call check(all_ok .and. placed, 'J2 block kernel, J from 0.6 to 1.5: every point the same '// &
               'bits at every place in blocks of 1 to '//trim(str(LD)))
  end subroutine check_large_volume_change

  !> *MAT_003 with BETA = 0.3 (back stress: the block polar rotation), points yielding from
  !> the virgin state: every point the same bits at every place in blocks of 1 to LD.
  subroutine check_kinematic_placement()
    real(wp) :: f_all(3, 3, LD), alone(6, LD)
    logical :: placed, all_ok
    integer :: i
    do i = 1, LD
      call random_f(PLASTIC_STRAIN, f_all(:, :, i))
    end do
    call place_points(kinematic_steel(), f_all, alone, all_ok, placed)
    call check(all_ok .and. placed, 'MAT_003 block kernel, BETA 0.3: every point the same '// &
               'bits at every place in blocks of 1 to '//trim(str(LD)))
  end subroutine check_kinematic_placement

  !> *MAT_003 with mixed hardening (BETA = 0.3: a back stress), steel (MPa, mm, t).
  type(material_t) function kinematic_steel() result(mat)
    mat = linear_steel()
    mat%kind = MAT_PLASTIC_KINEMATIC
    mat%beta = 0.3_wp
  end function kinematic_steel

  !> Points f_all(:, :, 1:LD) from the virgin state, each alone in a block (their stresses:
  !> alone), then in blocks of every length 1 to LD, shifted by the length (each point at
  !> many places): all updated (all_ok), each with the stress it gets alone (placed).
  subroutine place_points(mat, f_all, alone, all_ok, placed)
    type(material_t), intent(in) :: mat                !< the material
    real(wp), intent(in) :: f_all(3, 3, LD)            !< the points' deformation gradients
    real(wp), intent(out) :: alone(6, LD)              !< their stresses alone in a block
    logical, intent(out) :: all_ok, placed             !< every update ok; every stress equal
    real(wp) :: f(LD, 9), adj(LD, 9), det(LD), tau(LD, 6), hist(LD, NHIST)
    logical :: ok(LD)
    integer :: n, i, place
    do i = 1, LD
      call material_state_init(hist(1, :))
      f(1, :) = reshape(f_all(:, :, i), [9])
      call block_adjugate(1, f, adj, det)
      call material_update_block(mat, curves, 1, f, det, hist, tau, ok)
      alone(:, i) = tau(1, :)
    end do
    all_ok = .true.
    placed = .true.
    do n = 1, LD
      do i = 1, n
        place = 1 + mod(i + n - 1, LD)
        f(i, :) = reshape(f_all(:, :, place), [9])
        call material_state_init(hist(i, :))
      end do
      call block_adjugate(n, f, adj, det)
      call material_update_block(mat, curves, n, f, det, hist, tau, ok)
      do i = 1, n
        place = 1 + mod(i + n - 1, LD)
        all_ok = all_ok .and. ok(i)
        placed = placed .and. all(tau(i, :) == alone(:, place))
      end do
    end do
  end subroutine place_points

  !> Real as short text.
  function rtext(x) result(text)
    real(wp), intent(in) :: x                !< the number
    character(len=12) :: text
    write(text, '(g0.3)') x
  end function rtext

  !> *MAT_024 with 8 table points 0.002 apart (slopes changing at each): the plastic steps
  !> of check_material cross table points, so the block's one-step return map leaves points
  !> to return_map, whose results must be the same bits too.
  type(material_t) function fine_table_steel() result(mat)
    integer :: k
    mat = table_steel()
    mat%n_points = 8
    mat%eps = [(0.002_wp*real(k - 1, wp), k = 1, 8)]
    mat%es = [250.0_wp, 262.0_wp, 271.0_wp, 282.0_wp, 288.0_wp, 297.0_wp, 301.0_wp, 309.0_wp]
  end function fine_table_steel

  !> An inverted point in a block: reported, its history untouched; the others updated.
  subroutine check_failed_point()
    integer, parameter :: BAD = 4
    type(material_t) :: mat
    real(wp) :: hist(LD, NHIST), hist_before(LD, NHIST), f(LD, 9), det(LD), adj(LD, 9)
    real(wp) :: tau(LD, 6), f_point(3, 3), hist_new(NHIST), tau_point(3, 3), sound
    type(status_t) :: status
    logical :: ok(LD)
    integer :: i
    mat = linear_steel()
    do i = 1, NCELL
      call material_state_init(hist(i, :))
      call random_f(ELASTIC_STRAIN, f_point)
      if (i == BAD) f_point(:, 3) = -f_point(:, 3)          ! det < 0
      f(i, :) = reshape(f_point, [9])
    end do
    hist_before = hist
    call block_adjugate(NCELL, f, adj, det)
    call material_update_block(mat, curves, NCELL, f, det, hist, tau, ok)
    call check(.not. ok(BAD) .and. count(ok(1:NCELL)) == NCELL - 1, &
               'inverted point: reported, the others updated')
    call check(all(hist(BAD, :) == hist_before(BAD, :)), 'inverted point: history untouched')
    f_point = reshape(f(BAD + 1, :), [3, 3])
    call material_update(mat, curves, f_point, hist_before(BAD + 1, :), hist_new, tau_point, &
                         sound_speed=sound, status=status)
    call check(status%ok .and. all(hist(BAD + 1, :) == hist_new), 'its neighbour: updated as '// &
               'the point kernel updates it')
  end subroutine check_failed_point

  !> block_critical_omega_squared vs cell_critical_omega_squared.
  subroutine check_stable_step()
    real(wp) :: f(LD, 9), adj(LD, 9), det(LD), w0(LD, METRIC_ENTRIES), weight(LD), omega2(LD)
    real(wp) :: m(3, 3)
    real(wp) :: f_point(3, 3), w0_point(3, 3), worst, want, omega0(LD), quick(LD)
    integer :: i
    call random_number(weight)
    do i = 1, NCELL
      call random_f(0.3_wp, f_point)
      if (i == 1) f_point = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, &
                                     0.0_wp, 1.0_wp], [3, 3])
      if (i == 2) f_point(:, 1) = -f_point(:, 1)             ! det < 0
      f(i, :) = reshape(f_point, [9])
      call random_number(m)
      w0_point = matmul(m, transpose(m))                     ! symmetric positive
      w0_point = 0.5_wp*(w0_point + transpose(w0_point))     ! (to the bit)
      if (i == 1) w0_point = reshape([2.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 0.0_wp, &
                                      0.0_wp, 2.0_wp], [3, 3])   ! isotropic: triple root
      w0(i, :) = metric_packed(w0_point)
      if (i == 3) call check(all(metric_unpacked(w0(i, :)) == w0_point), &
                             'stable step: a packed metric unpacks to the same bits')
    end do
    call block_adjugate(NCELL, f, adj, det)
    call block_critical_omega_squared(NCELL, weight, w0, adj, det, LAMBDA, MU, omega2)
    worst = 0.0_wp
    do i = 3, NCELL
      want = cell_critical_omega_squared(3, weight(i), metric_unpacked(w0(i, :)), &
                                         reshape(f(i, :), [3, 3]), LAMBDA, MU)
      worst = max(worst, abs(omega2(i) - want)/want)
    end do
    call check(worst <= 1.0e-13_wp, 'stable step: random cells within 1e-13 of the point '// &
               'kernel (worst '//trim(rstr(worst))//')')
    want = cell_critical_omega_squared(3, weight(1), metric_unpacked(w0(1, :)), &
                                       reshape(f(1, :), [3, 3]), LAMBDA, MU)
    call check_close(omega2(1), want, 1.0e-15_wp, 'stable step: isotropic metric at F = I')
    call check_close(omega2(1), weight(1)*2.0_wp*(3.0_wp*LAMBDA + 2.0_wp*MU), 1.0e-15_wp, &
                     'stable step: isotropic metric, closed form w (3 lambda + 2 mu) tr/3')
    call check(omega2(2) == huge(1.0_wp), 'stable step: det F < 0 gives huge')
    ! the quick bound: above the exact one everywhere, equal at F = I, huge for det F < 0
    do i = 1, NCELL
      omega0(i) = cell_reference_bound(metric_unpacked(w0(i, :)), LAMBDA, MU)
    end do
    call block_quick_omega_squared(NCELL, weight, omega0, adj, det, quick)
    worst = huge(1.0_wp)
    do i = 3, NCELL
      worst = min(worst, quick(i)/omega2(i))
    end do
    call check(worst >= 1.0_wp - 1.0e-14_wp, 'stable step: the quick bound is above the '// &
               'exact one in every random cell (smallest ratio '//trim(rstr(worst))//')')
    call check_close(quick(1), omega2(1), 1.0e-14_wp, 'stable step: quick bound = exact at F = I')
    call check(quick(2) == huge(1.0_wp), 'stable step: quick bound, det F < 0 gives huge')
    ! and a cell compressed along one axis: adj = diag(1, 0.8, 0.8), lambda_max(adj^T adj) = 1
    ! with the two others equal below it, where the quick bound of it is exact
    f(3, :) = [0.8_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp]
    w0(3, :) = metric_packed(reshape([2.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, &
                                      0.0_wp, 0.0_wp, 2.0_wp], [3, 3]))
    omega0(3) = cell_reference_bound(metric_unpacked(w0(3, :)), LAMBDA, MU)
    call block_adjugate(3, f, adj, det)
    call block_quick_omega_squared(3, weight, omega0, adj, det, quick)
    ! omega^2 <= (w/J) lambda_max(adj^T adj) omega_0, J = 0.8, omega_0 = 2 (3 lambda + 2 mu)
    call check_close(quick(3), weight(3)/0.8_wp*2.0_wp*(3.0_wp*LAMBDA + 2.0_wp*MU), &
                     1.0e-14_wp, 'stable step: quick bound of a compressed cell, closed form')
  end subroutine check_stable_step

  !> The same cell in blocks of other lengths and at other places gives the same bits (7-node
  !> cells with full or with compact face gradients).
  subroutine check_placement(face)
    logical, intent(in) :: face            !< the face kernels (compact gradients)
    integer, parameter :: NN = 7
    real(wp) :: u(LD, 3, CELL_MAX_NODES), grad(LD, 3, CELL_MAX_NODES), w0(LD, METRIC_ENTRIES)
    real(wp) :: weight(LD)
    real(wp) :: hist(LD, NHIST), omega2(LD), force(LD, 3, CELL_MAX_NODES), m(3, 3)
    real(wp) :: ref_force(3, NN), ref_hist(NHIST), ref_omega2
    logical :: same
    integer :: n, place, i
    call random_number(u)
    u = PLASTIC_STRAIN*(u - 0.5_wp)
    call random_number(grad)
    grad = grad - 0.5_wp
    call random_number(weight)
    do i = 1, LD
      call random_number(m)
      w0(i, :) = metric_packed(matmul(m, transpose(m)))
    end do
    call run_block(1, 1, NN, face, u, grad, w0, weight, hist, force, omega2)   ! cell 1 alone
    ref_force = force(1, :, 1:NN)
    ref_hist = hist(1, :)
    ref_omega2 = omega2(1)
    same = .true.
    do n = 2, LD
      place = 1 + mod(7*n + 3, n)          ! places 1 .. n
      call run_block(n, place, NN, face, u, grad, w0, weight, hist, force, omega2)
      same = same .and. all(force(place, :, 1:NN) == ref_force) .and. &
             all(hist(place, :) == ref_hist) .and. omega2(place) == ref_omega2
    end do
    call check(same, 'a cell gives the same bits at any place in blocks of 1 to '// &
               trim(str(LD))//' cells'//trim(merge(' (compact face gradients)', &
                                                   '                         ', face)))
  end subroutine check_placement

  !> The kernels on a block of n cells of a table-hardening material from the virgin state,
  !> cell 1's data copied to `place` and new random displacements elsewhere.
  subroutine run_block(n, place, nn, face, u, grad, w0, weight, hist, force, omega2)
    integer, intent(in) :: n, place, nn        !< block length, reference place, nodes
    logical, intent(in) :: face                !< the face kernels (nn = 7, compact gradients)
    real(wp), intent(inout) :: u(LD, 3, CELL_MAX_NODES), grad(LD, 3, CELL_MAX_NODES) !< data
    real(wp), intent(inout) :: w0(LD, METRIC_ENTRIES), weight(LD)                      !< data
    real(wp), intent(out) :: hist(LD, NHIST)                     !< histories after the step
    real(wp), intent(out) :: force(LD, 3, CELL_MAX_NODES)        !< forces
    real(wp), intent(out) :: omega2(LD)                          !< stable-step bounds
    real(wp) :: f(LD, 9), adj(LD, 9), det(LD), tau(LD, 6), omega0(LD), quick(LD)
    logical :: ok(LD)
    integer :: i
    call random_number(u(2:LD, :, :))
    u(2:LD, :, :) = PLASTIC_STRAIN*(u(2:LD, :, :) - 0.5_wp)
    u(place, :, 1:nn) = u(1, :, 1:nn)
    grad(place, :, 1:nn) = grad(1, :, 1:nn)
    w0(place, :) = w0(1, :)
    weight(place) = weight(1)
    do i = 1, n
      call material_state_init(hist(i, :))
    end do
    if (face) then
      call block_face_deformation_gradient(n, u, grad, f)
    else
      call block_deformation_gradient(n, nn, u, grad, f)
    end if
    call block_adjugate(n, f, adj, det)
    call material_update_block(table_steel(), curves, n, f, det, hist, tau, ok)
    if (face) then
      call block_face_internal_force(n, grad, weight, adj, det, tau, force)
    else
      call block_internal_force(n, nn, grad, weight, adj, det, tau, force)
    end if
    call block_critical_omega_squared(n, weight, w0, adj, det, LAMBDA, MU, omega2)
    ! the quick bound in omega2's imaginary place: added, as a check of its bits too
    do i = 1, n
      omega0(i) = cell_reference_bound(metric_unpacked(w0(i, :)), LAMBDA, MU)
    end do
    call block_quick_omega_squared(n, weight, omega0, adj, det, quick)
    do i = 1, n
      omega2(i) = omega2(i) + quick(i)
    end do
  end subroutine run_block

  !> Integer as text.
  function str(k) result(text)
    integer, intent(in) :: k                 !< the number
    character(len=12) :: text
    write(text, '(i0)') k
  end function str

  !> Real as text.
  function rstr(x) result(text)
    real(wp), intent(in) :: x                !< the number
    character(len=16) :: text
    write(text, '(es10.3)') x
  end function rstr

end program test_block_kernels
