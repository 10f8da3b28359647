!> The nodal-pressure tetrahedron (ELFORM 13) of the implicit analysis
!> (mefem_implicit_nodal_pressure): the assembled tangent, each element's own part plus the
!> block of the means on its patch, is the derivative of the assembled forces (central
!> differences) on a distorted mesh of 24 tets: J2 plasticity in plastic flow, the compressible
!> neo-Hookean of *MAT_ELASTIC (whose pressure depends on the deviatoric state: the T and M
!> terms) and both materials in one mesh (nodes where they meet take the element's own J and
!> p); the node-pair sums that the analysis hands to the solver hold the same matrix. The
!> means: the coefficients of each element sum to 1 and V0_e c_eh = V0_h c_he; in an
!> affine motion every Jbar equals J and the forces are the standard tet's.
program test_nodal_pressure_tangent
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_strings, only: rtoa
  use mefem_model, only: material_t, curve_t
  use mefem_cells, only: cells_t, CELL_MAX_NODES
  use mefem_cell_finite_strain, only: cell_internal_force, cell_tangent
  use mefem_material_state, only: NHIST, material_state_init
  use mefem_material_update, only: material_update
  use mefem_errors, only: status_t
  use mefem_implicit_nodal_pressure, only: np_patches_t, np_values_t, np_patches_build, &
                                           np_pairs_build, np_prepare, np_pressures, np_fbar, &
                                           np_cell_terms, np_add_to_pairs
  use mefem_test_fixtures, only: linear_steel, elastic_steel
  implicit none

  integer, parameter :: NX = 2, NY = 2, NZ = 1
  integer, parameter :: NNODE = (NX + 1)*(NY + 1)*(NZ + 1), NCELL = 6*NX*NY*NZ
  type(cells_t) :: cells
  type(np_patches_t) :: patches
  type(material_t) :: materials(2)
  type(curve_t) :: curves(0)
  real(wp) :: x0(3, NNODE)

  call test_start('nodal_pressure_tangent')
  call fixed_seed()
  materials(1) = linear_steel()
  materials(2) = elastic_steel()
  call build_mesh()
  call check_means()
  call check_affine()
  call check_tangent('J2 plasticity, plastic flow', [1, 1], 1.0e-2_wp)
  call check_tangent('compressible neo-Hookean', [2, 2], 1.0e-2_wp)
  call check_tangent('two materials (own J and p where they meet)', [1, 2], 1.0e-2_wp)
  call test_finish()

contains

  !> The same random numbers in every run (the figures in doc/verification.md).
  subroutine fixed_seed()
    integer :: n, k
    call random_seed(size=n)
    call random_seed(put=[(12345 + 7*k, k = 1, n)])
  end subroutine fixed_seed

  !> A box of NX x NY x NZ cubes, 6 tets each, nodes moved at random by up to 0.15.
  subroutine build_mesh()
    integer, parameter :: KUHN(4, 6) = reshape([1, 2, 3, 7, 1, 3, 4, 7, 1, 4, 8, 7, &
                                                1, 8, 5, 7, 1, 5, 6, 7, 1, 6, 2, 7], [4, 6])
    integer :: i, j, k, n, c, corner(8), t, swap
    real(wp) :: r(3), m(3, 3), inv(3, 3), det
    n = 0
    do k = 0, NZ
      do j = 0, NY
        do i = 0, NX
          n = n + 1
          call random_number(r)
          x0(:, n) = [real(i, wp), real(j, wp), real(k, wp)] + 0.3_wp*(r - 0.5_wp)
        end do
      end do
    end do
    cells%dim = 3
    cells%n = NCELL
    cells%n_mesh_nodes = NNODE
    allocate(cells%nnodes(NCELL), cells%nodes(CELL_MAX_NODES, NCELL), &
             cells%grad(3, CELL_MAX_NODES, NCELL), cells%weight(NCELL), cells%material(NCELL), &
             cells%nodal_pressure(NCELL), cells%elements(2, NCELL))
    cells%nodes = 0
    cells%grad = 0.0_wp
    c = 0
    do k = 0, NZ - 1
      do j = 0, NY - 1
        do i = 0, NX - 1
          corner(1:4) = [node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), &
                         node(i, j + 1, k)]
          corner(5:8) = corner(1:4) + (NX + 1)*(NY + 1)
          do t = 1, 6
            c = c + 1
            cells%nodes(1:4, c) = corner(KUHN(:, t))
            m = x0(:, cells%nodes(2:4, c)) - spread(x0(:, cells%nodes(1, c)), 2, 3)
            call invert(m, inv, det)
            if (det < 0.0_wp) then                    ! positive orientation
              swap = cells%nodes(3, c)
              cells%nodes(3, c) = cells%nodes(4, c)
              cells%nodes(4, c) = swap
              m = x0(:, cells%nodes(2:4, c)) - spread(x0(:, cells%nodes(1, c)), 2, 3)
              call invert(m, inv, det)
            end if
            cells%weight(c) = det/6.0_wp
            cells%grad(:, 2:4, c) = transpose(inv)    ! rows of inv: gradients of N2..N4
            cells%grad(:, 1, c) = -sum(cells%grad(:, 2:4, c), dim=2)
          end do
        end do
      end do
    end do
    cells%nnodes = 4
    cells%material = 1
    cells%nodal_pressure = .true.
    cells%elements = 0
    call np_patches_build(cells, patches)
  end subroutine build_mesh

  !> The box's node at grid point (i, j, k).
  pure integer function node(i, j, k)
    integer, intent(in) :: i, j, k
    node = 1 + i + (NX + 1)*(j + (NY + 1)*k)
  end function node

  !> Inverse and determinant of a 3x3 matrix (cofactors).
  pure subroutine invert(m, inv, det)
    real(wp), intent(in) :: m(3, 3)
    real(wp), intent(out) :: inv(3, 3), det
    inv(1, 1) = m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)
    inv(1, 2) = m(1, 3)*m(3, 2) - m(1, 2)*m(3, 3)
    inv(1, 3) = m(1, 2)*m(2, 3) - m(1, 3)*m(2, 2)
    inv(2, 1) = m(2, 3)*m(3, 1) - m(2, 1)*m(3, 3)
    inv(2, 2) = m(1, 1)*m(3, 3) - m(1, 3)*m(3, 1)
    inv(2, 3) = m(1, 3)*m(2, 1) - m(1, 1)*m(2, 3)
    inv(3, 1) = m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1)
    inv(3, 2) = m(1, 2)*m(3, 1) - m(1, 1)*m(3, 2)
    inv(3, 3) = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
    det = m(1, 1)*inv(1, 1) + m(1, 2)*inv(2, 1) + m(1, 3)*inv(3, 1)
    inv = inv/det
  end subroutine invert

  !> The coefficients of each element's means sum to 1; V0_e c_eh = V0_h c_he.
  subroutine check_means()
    real(wp) :: worst_sum, worst_sym, c(NCELL, NCELL)
    integer :: e, k
    c = 0.0_wp
    worst_sum = 0.0_wp
    do e = 1, patches%n
      do k = patches%term_start(e), patches%term_start(e + 1) - 1
        c(e, patches%term(k)) = patches%coef(k)
      end do
      worst_sum = max(worst_sum, abs(sum(c(e, :)) - 1.0_wp))
    end do
    worst_sym = 0.0_wp
    do e = 1, NCELL
      worst_sym = max(worst_sym, maxval(abs(cells%weight(e)*c(e, :) - cells%weight*c(:, e)))/ &
                                 cells%weight(e))
    end do
    call check(worst_sum < 1.0e-14_wp, 'every element''s coefficients sum to 1', &
               rtoa(worst_sum))
    call check(worst_sym < 1.0e-14_wp, 'V0_e c_eh = V0_h c_he', rtoa(worst_sym))
  end subroutine check_means

  !> An affine motion: every Jbar equals J, and the forces are the standard tet's.
  subroutine check_affine()
    real(wp) :: u(3, NNODE), g(3, 3), f_np(3, NNODE), f_std(3, NNODE)
    real(wp) :: hist(NHIST, NCELL), hist_new(NHIST), tau(3, 3), sound, fc(3, 4)
    type(np_values_t) :: values
    type(status_t) :: status
    logical :: ok
    integer :: n, l, bad
    g = reshape([-0.02_wp, 0.003_wp, 0.001_wp, 0.004_wp, 0.01_wp, -0.002_wp, 0.0_wp, &
                 0.005_wp, 0.008_wp], [3, 3])
    do n = 1, NNODE
      u(:, n) = matmul(g, x0(:, n))
    end do
    cells%material = 1
    do l = 1, NCELL
      call material_state_init(hist(:, l))
    end do
    call np_prepare(cells, patches, u, values, ok, bad)
    call check(ok .and. maxval(abs(values%jbar/values%det - 1.0_wp)) < 1.0e-14_wp, &
               'affine motion: Jbar = J in every element', rtoa(maxval(abs(values%jbar/ &
               values%det - 1.0_wp))))
    call assemble(u, hist, f_np)
    f_std = 0.0_wp
    do l = 1, NCELL
      call material_update(materials(1), curves, values%f(:, :, l), hist(:, l), hist_new, &
                           tau, sound_speed=sound, status=status)
      call cell_internal_force(3, 4, cells%grad(:, :, l), cells%weight(l), values%f(:, :, l), &
                               tau, fc)
      f_std(:, cells%nodes(1:4, l)) = f_std(:, cells%nodes(1:4, l)) + fc
    end do
    call check_close(reshape(f_np, [3*NNODE]), reshape(f_std, [3*NNODE]), 1.0e-12_wp, &
                     'affine motion: the standard tet''s forces', atol=1.0e-9_wp*maxval(abs(f_std)))
  end subroutine check_affine

  !> The assembled tangent against central differences of the assembled forces, with the
  !> materials kinds(1) on the first half of the elements and kinds(2) on the rest.
  subroutine check_tangent(name, kinds, scale)
    character(len=*), intent(in) :: name
    integer, intent(in) :: kinds(2)
    real(wp), intent(in) :: scale                     !< size of the random displacements
    real(wp) :: u(3, NNODE), up(3, NNODE), hist(NHIST, NCELL), r(3, NNODE), g(3, 3)
    real(wp) :: k_assembled(3*NNODE, 3*NNODE), k_fd(3*NNODE, 3*NNODE)
    real(wp) :: fp(3, NNODE), fm(3, NNODE), f0(3, NNODE), h, error
    integer :: n, j, l, comp
    cells%material(1:NCELL/2) = kinds(1)
    cells%material(NCELL/2 + 1:) = kinds(2)
    call np_patches_build(cells, patches)
    do l = 1, NCELL
      call material_state_init(hist(:, l))
    end do
    g = reshape([-0.02_wp, 0.003_wp, 0.001_wp, 0.004_wp, 0.01_wp, -0.002_wp, 0.0_wp, &
                 0.005_wp, 0.008_wp], [3, 3])
    call random_number(r)
    do n = 1, NNODE
      u(:, n) = matmul(g, x0(:, n)) + scale*(r(:, n) - 0.5_wp)
    end do
    call assemble(u, hist, f0, k_assembled)
    h = 1.0e-6_wp
    do j = 1, 3*NNODE
      comp = mod(j - 1, 3) + 1
      n = 1 + (j - comp)/3
      up = u
      up(comp, n) = u(comp, n) + h
      call assemble(up, hist, fp)
      up(comp, n) = u(comp, n) - h
      call assemble(up, hist, fm)
      k_fd(:, j) = reshape(fp - fm, [3*NNODE])/(2.0_wp*h)
    end do
    error = maxval(abs(k_assembled - k_fd))/maxval(abs(k_fd))
    print '(a, es9.2)', '    '//name//': largest tangent error / largest entry ', error
    call check(error < 1.0e-6_wp, name//': tangent = derivative of the forces (central '// &
               'differences, largest entry)', rtoa(error))
    ! the analysis sums the blocks per node pair (np_add_to_pairs): the same matrix
    call assemble(u, hist, f0, k_fd, pairs=.true.)
    error = maxval(abs(k_assembled - k_fd))/maxval(abs(k_assembled))
    call check(error < 1.0e-14_wp, name//': the node-pair sums hold the same tangent', &
               rtoa(error))
    ! the means' block matters: without it the tangent is far off
    call assemble(u, hist, f0, k_assembled, local_only=.true.)
    error = maxval(abs(k_assembled - k_fd))/maxval(abs(k_fd))
    print '(a, es9.2)', '    '//name//': the same without the means'' block ', error
    call check(error > 1.0e-3_wp, name//': the elements'' own tangents alone are not it', &
               rtoa(error))
  end subroutine check_tangent

  !> Forces (and tangent) of all elements at u from the history hist, as the implicit
  !> analysis assembles them.
  subroutine assemble(u, hist, force, stiffness, local_only, pairs)
    real(wp), intent(in) :: u(:,:), hist(:,:)
    real(wp), intent(out) :: force(3, NNODE)
    real(wp), intent(out), optional :: stiffness(3*NNODE, 3*NNODE)
    logical, intent(in), optional :: local_only
    logical, intent(in), optional :: pairs         !< the blocks through the node-pair sums
    real(wp), allocatable :: pair_values(:,:,:)
    logical :: by_pairs
    integer :: n, k
    type(np_values_t) :: values
    type(status_t) :: status
    real(wp) :: hist_new(NHIST), sound, tau(3, 3), c(3, 3, 3, 3), fc(3, 4), ke(12, 12)
    real(wp) :: block(3*patches%max_patch, 3*patches%max_patch)
    integer :: e, l, bad, dofs(12), np, first, a, i
    integer :: patch_dofs(3*patches%max_patch)
    logical :: ok
    call np_prepare(cells, patches, u, values, ok, bad)
    do e = 1, patches%n
      l = patches%cell(e)
      call material_update(materials(cells%material(l)), curves, np_fbar(values, e), &
                           hist(:, l), hist_new, values%tau(:, :, e), values%c(:, :, :, :, e), &
                           sound, status)
    end do
    call np_pressures(patches, values)
    force = 0.0_wp
    if (present(stiffness)) stiffness = 0.0_wp
    by_pairs = .false.
    if (present(pairs)) by_pairs = pairs
    if (by_pairs) then
      call np_pairs_build(patches, [(.true., l = 1, NCELL)])
      allocate(pair_values(3, 3, size(patches%pair_node)))
      pair_values = 0.0_wp
    end if
    do e = 1, patches%n
      l = patches%cell(e)
      call np_cell_terms(cells, patches, values, e, tau, c, block)
      call cell_internal_force(3, 4, cells%grad(:, :, l), cells%weight(l), values%f(:, :, e), &
                               tau, fc)
      force(:, cells%nodes(1:4, l)) = force(:, cells%nodes(1:4, l)) + fc
      if (.not. present(stiffness)) cycle
      call cell_tangent(3, 4, cells%grad(:, :, l), cells%weight(l), values%f(:, :, e), tau, c, &
                        ke)
      do a = 1, 4
        do i = 1, 3
          dofs(3*(a - 1) + i) = 3*(cells%nodes(a, l) - 1) + i
        end do
      end do
      stiffness(dofs, dofs) = stiffness(dofs, dofs) + ke
      if (present(local_only)) then
        if (local_only) cycle
      end if
      if (by_pairs) then
        call np_add_to_pairs(patches, e, block, pair_values)
        cycle
      end if
      first = patches%patch_start(e)
      np = patches%patch_start(e + 1) - first
      do a = 1, np
        do i = 1, 3
          patch_dofs(3*(a - 1) + i) = 3*(patches%patch_node(first + a - 1) - 1) + i
        end do
      end do
      stiffness(patch_dofs(1:3*np), patch_dofs(1:3*np)) = &
          stiffness(patch_dofs(1:3*np), patch_dofs(1:3*np)) + block(1:3*np, 1:3*np)
    end do
    if (.not. by_pairs) return
    do n = 1, size(patches%pair_start) - 1
      do k = patches%pair_start(n), patches%pair_start(n + 1) - 1
        stiffness(3*n-2:3*n, 3*patches%pair_node(k)-2:3*patches%pair_node(k)) = &
            stiffness(3*n-2:3*n, 3*patches%pair_node(k)-2:3*patches%pair_node(k)) + &
            pair_values(:, :, k)
      end do
    end do
  end subroutine assemble

end program test_nodal_pressure_tangent
