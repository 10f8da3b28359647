!> Stable time step of the explicit solver (mefem_stable_time_step, formulation 2.9):
!> - the closed-form largest eigenvalue of symmetric 2x2/3x3 matrices against LAPACK dsyev;
!> - material_elastic_moduli against each law's tangent at F = I (c_1122 = lambda,
!>   c_1212 = mu);
!> - regular simplex (equilateral triangle, regular tetrahedron), standard element: the bound
!>   equals the exact largest eigenvalue of (K, M) and its closed form, also for nu < 0;
!> - on a cube of 5-tet cubes (regular, distorted) and a square of triangles (distorted,
!>   regular), ME-FEM, standard and mixed: the cell shares sum to lumped_mass; every cell's
!>   bound is >= the exact largest generalized eigenvalue of its dense (K_c, M_c), and within
!>   1/0.85 of it; the global lambda_max(M^-1 K) (power iteration, checked against dsyev) is
!>   <= the largest cell bound, with the equal and the stiffness-weighted mass split, and the
!>   measured ratio of the weighted split is asserted; the bound at a homogeneous F
!>   equals the bound of the cells rebuilt in the deformed geometry (density rho/J: the same
!>   masses).
!> K is assembled here from the cell gradients and the isotropic C_ijkl (independent of
!> mefem_cell_linear).
program test_stable_time_step
  use, intrinsic :: iso_fortran_env, only: output_unit
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t
  use mefem_strings, only: rtoa
  use mefem_model, only: model_t, material_t, curve_t, ELEM_SOLID, ELEM_SHELL, SECTION_SOLID, &
                         SECTION_SHELL, MAT_ELASTIC, MAT_PIECEWISE_LINEAR, MAT_POWER_LAW, &
                         MAT_MOONEY_RIVLIN, MAT_RIGID, TOPO_TET4, TOPO_TRI3
  use mefem_model_resolve, only: ELFORM_MEFEM, ELFORM_TET_STANDARD, ELFORM_TRI_PLANE_STRAIN
  use mefem_cells, only: cells_t, cells_build, CELL_MAX_NODES, cell_grad_column
  use mefem_lumped_mass, only: lumped_mass
  use mefem_cell_finite_strain, only: face_gradients_compact, face_gradients_expanded
  use mefem_material_state, only: NHIST, material_state_init
  use mefem_material_update, only: material_update, material_elastic_moduli
  use mefem_stable_time_step, only: cell_mass_shares, cell_inverse_mass_metric, &
                                    cell_critical_omega_squared, symmetric_max_eigenvalue, &
                                    cell_split_weights, inverse_mass_metric, &
                                    cell_rebalance_weights
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal
  implicit none

  interface
    !> LAPACK: eigenvalues (and vectors) of a symmetric matrix.
    subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: wp
      character, intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(wp), intent(inout) :: a(lda, *)
      real(wp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev
  end interface

  real(wp), parameter :: DENSITY_MEFEM = 7.8_wp, DENSITY_STANDARD = 2.7_wp
  real(wp), parameter :: YOUNG_MEFEM = 200.0_wp, YOUNG_STANDARD = 70.0_wp
  real(wp), parameter :: POISSON_MEFEM = 0.3_wp, POISSON_STANDARD = 0.33_wp
  integer, parameter :: PART_MEFEM = 1, PART_STANDARD = 2, PART_MIXED = 3
  !> homogeneous deformations for the current-configuration check (det 2D 0.9075, 3D 1.0799)
  real(wp), parameter :: F_2D(3, 3) = reshape([1.15_wp, -0.1_wp, 0.0_wp, 0.3_wp, 0.85_wp, &
                                               0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  real(wp), parameter :: F_3D(3, 3) = reshape([1.15_wp, 0.05_wp, -0.1_wp, 0.2_wp, 0.9_wp, &
                                               0.1_wp, -0.1_wp, 0.25_wp, 1.05_wp], [3, 3])
  real(wp), parameter :: IDENTITY(3, 3) = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, &
                                                   0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])

  call test_start('stable_time_step')
  call check_eigenvalue_closed_form()
  call check_material_moduli()
  call check_regular_simplex(2)
  call check_regular_simplex(3)
  ! global ratio limits (max cell bound / lambda_max(M^-1 K)): measured values in
  ! check_mesh's comment
  call check_mesh('tet 5-cube ME-FEM', 3, 3, 0.0_wp, PART_MEFEM, 2.2_wp)
  call check_mesh('tet 5-cube standard', 3, 3, 0.0_wp, PART_STANDARD, 1.7_wp)
  call check_mesh('tet 5-cube distorted ME-FEM', 3, 3, 0.25_wp, PART_MEFEM, 3.3_wp)
  call check_mesh('tet 5-cube distorted standard', 3, 3, 0.25_wp, PART_STANDARD, 3.4_wp)
  call check_mesh('tet 5-cube mixed', 3, 2, 0.0_wp, PART_MIXED, 2.45_wp)
  call check_mesh('tri distorted ME-FEM', 2, 8, 0.3_wp, PART_MEFEM, 2.5_wp)
  call check_mesh('tri distorted standard', 2, 8, 0.3_wp, PART_STANDARD, 2.75_wp)
  call check_mesh('tri regular mixed', 2, 6, 0.0_wp, PART_MIXED, 3.1_wp)
  call check_kept_gradients(3, 3, 0.25_wp)
  call check_kept_gradients(2, 6, 0.3_wp)
  call check_face_layout()
  call test_finish()

contains

  ! ------------------------------------------------------------------ small helpers

  !> Deterministic pseudo-random number in [-0.5, 0.5) from two integers.
  pure real(wp) function hash(i, j)
    integer, intent(in) :: i, j                   !< seeds
    real(wp) :: s
    s = sin(real(i, wp)*12.9898_wp + real(j, wp)*78.233_wp)*43758.5453_wp
    hash = s - floor(s) - 0.5_wp
  end function hash

  !> Eigenvalues (ascending) of a dense symmetric matrix by LAPACK dsyev.
  subroutine eigenvalues(a, w)
    real(wp), intent(in) :: a(:,:)                !< symmetric matrix
    real(wp), intent(out) :: w(:)                 !< its eigenvalues, ascending
    real(wp), allocatable :: copy(:,:), work(:)
    integer :: n, info
    n = size(a, 1)
    copy = a
    allocate(work(max(1, 3*n)*8))
    call dsyev('N', 'U', n, copy, n, w, work, size(work), info)
    if (info /= 0) w = huge(1.0_wp)
  end subroutine eigenvalues

  !> Print an informational line (measured values; not counted as a check).
  subroutine info(text)
    character(len=*), intent(in) :: text          !< the line
    write(output_unit, '(a)') 'info: '//text
  end subroutine info

  !> Isotropic elasticity C_ijkl = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk).
  pure real(wp) function elasticity(lambda, mu, i, j, k, l)
    real(wp), intent(in) :: lambda, mu            !< Lame constants
    integer, intent(in) :: i, j, k, l             !< indices
    elasticity = lambda*delta(i, j)*delta(k, l) + mu*(delta(i, k)*delta(j, l) + &
                 delta(i, l)*delta(j, k))
  end function elasticity

  !> Kronecker delta.
  pure real(wp) function delta(i, j)
    integer, intent(in) :: i, j                   !< indices
    delta = merge(1.0_wp, 0.0_wp, i == j)
  end function delta

  !> Dense small-strain stiffness of a cell: K(dim(I-1)+i, dim(J-1)+k) =
  !> A sum_jl g_Ij C_ijkl g_Jl (plane strain: in-plane indices only).
  pure subroutine dense_cell_stiffness(dim, nn, grad, weight, lambda, mu, k_cell)
    integer, intent(in) :: dim, nn                !< dimension, nodes
    real(wp), intent(in) :: grad(:,:)             !< (dim, >= nn) gradients
    real(wp), intent(in) :: weight, lambda, mu    !< cell measure, Lame constants
    real(wp), intent(out) :: k_cell(:,:)          !< (dim nn, dim nn)
    integer :: a, b, i, j, k, l
    real(wp) :: s
    do b = 1, nn
      do k = 1, dim
        do a = 1, nn
          do i = 1, dim
            s = 0.0_wp
            do j = 1, dim
              do l = 1, dim
                s = s + grad(j, a)*elasticity(lambda, mu, i, j, k, l)*grad(l, b)
              end do
            end do
            k_cell(dim*(a - 1) + i, dim*(b - 1) + k) = weight*s
          end do
        end do
      end do
    end do
  end subroutine dense_cell_stiffness

  !> Exact largest eigenvalue of (K_c, M_c), M_c = diag(shares), by dsyev on M^-1/2 K M^-1/2.
  real(wp) function cell_exact_omega_squared(dim, nn, grad, weight, share, lambda, mu)
    integer, intent(in) :: dim, nn                !< dimension, nodes
    real(wp), intent(in) :: grad(:,:), weight     !< gradients, measure
    real(wp), intent(in) :: share(:)              !< (>= nn) mass shares
    real(wp), intent(in) :: lambda, mu            !< Lame constants
    real(wp) :: k_cell(dim*nn, dim*nn), scale(dim*nn), w(dim*nn)
    integer :: a, i
    call dense_cell_stiffness(dim, nn, grad, weight, lambda, mu, k_cell)
    do a = 1, nn
      do i = 1, dim
        scale(dim*(a - 1) + i) = 1.0_wp/sqrt(share(a))
      end do
    end do
    do i = 1, dim*nn
      k_cell(:, i) = k_cell(:, i)*scale*scale(i)
    end do
    call eigenvalues(k_cell, w)
    cell_exact_omega_squared = w(dim*nn)
  end function cell_exact_omega_squared

  ! ------------------------------------------------------------------ models

  !> Model from coordinates and connectivity; part 1 ME-FEM (material 1), part 2 standard
  !> (material 2), both *MAT_ELASTIC.
  subroutine build_model(dim, x, conn, part, model)
    integer, intent(in) :: dim                    !< 2 or 3
    real(wp), intent(in) :: x(:,:)                !< (3, nnode) coordinates
    integer, intent(in) :: conn(:,:)              !< (dim+1, nelem) corners
    integer, intent(in) :: part(:)                !< (nelem) 1 or 2
    type(model_t), intent(out) :: model           !< the model
    integer :: nnode, nelem, i
    nnode = size(x, 2)
    nelem = size(conn, 2)
    model%dimension = dim
    model%nodes%n = nnode
    model%nodes%id = [(i, i = 1, nnode)]
    model%nodes%x = x
    model%elements%n = nelem
    model%elements%id = [(i, i = 1, nelem)]
    model%elements%part = part
    model%elements%part_id = part
    allocate(model%elements%keyword(nelem), model%elements%topology(nelem), &
             model%elements%conn(8, nelem))
    model%elements%conn = 0
    model%elements%conn(1:dim + 1, :) = conn
    model%elements%keyword = merge(ELEM_SOLID, ELEM_SHELL, dim == 3)
    model%elements%topology = merge(TOPO_TET4, TOPO_TRI3, dim == 3)
    model%n_parts = 2
    allocate(model%parts(2))
    model%parts%id = [1, 2]
    model%parts%section = [1, 2]
    model%parts%material = [1, 2]
    model%n_sections = 2
    allocate(model%sections(2))
    model%sections%kind = merge(SECTION_SOLID, SECTION_SHELL, dim == 3)
    model%sections(1)%elform = ELFORM_MEFEM
    ! without ME-FEM elements, part 1 is standard too (no enrichment set-up)
    if (all(part /= 1)) model%sections(1)%elform = merge(ELFORM_TET_STANDARD, &
                                                         ELFORM_TRI_PLANE_STRAIN, dim == 3)
    model%sections(2)%elform = merge(ELFORM_TET_STANDARD, ELFORM_TRI_PLANE_STRAIN, dim == 3)
    model%n_materials = 2
    allocate(model%materials(2))
    model%materials%kind = MAT_ELASTIC
    model%materials%id = [1, 2]
    model%materials%density = [DENSITY_MEFEM, DENSITY_STANDARD]
    model%materials%young = [YOUNG_MEFEM, YOUNG_STANDARD]
    model%materials%poisson = [POISSON_MEFEM, POISSON_STANDARD]
    model%controls%gmf_basis = 1
    model%controls%support_radius = 1.5_wp
  end subroutine build_model

  !> Box [0,1]^3 of n^3 cubes of 5 tets (the central tet on the lattice points of even
  !> i+j+k, so neighbouring cubes match), or the square [0,1]^2 of n^2 squares of 2
  !> triangles (alternating diagonals). Interior nodes are moved by up to jitter x spacing
  !> in each direction. Parts: all ME-FEM, all standard, or mixed (x < 1/2 ME-FEM).
  subroutine make_mesh(dim, n, jitter, parts, model)
    integer, intent(in) :: dim, n                 !< dimension, cells per direction
    real(wp), intent(in) :: jitter                !< relative node perturbation
    integer, intent(in) :: parts                  !< PART_MEFEM, PART_STANDARD, PART_MIXED
    type(model_t), intent(out) :: model           !< the model
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:), part(:)
    integer :: nnode, i, j, k, e, a, odd, corner(3), nz, t
    integer :: lattice_of(0:1, 0:1, 0:1)
    real(wp) :: h
    h = 1.0_wp/n
    nz = merge(n, 0, dim == 3)
    nnode = (n + 1)**2*(nz + 1)
    allocate(x(3, nnode))
    x = 0.0_wp
    do k = 0, nz
      do j = 0, n
        do i = 0, n
          a = node_of(n, i, j, k)
          x(:, a) = [i, j, k]*h
          if (min(i, j) > 0 .and. max(i, j) < n .and. (dim == 2 .or. &
              (k > 0 .and. k < n))) then
            x(1:dim, a) = x(1:dim, a) + jitter*h*2.0_wp*[(hash(a, t), t = 1, dim)]
          end if
        end do
      end do
    end do
    if (dim == 3) then
      allocate(conn(4, 5*n**3))
      e = 0
      do k = 0, n - 1
        do j = 0, n - 1
          do i = 0, n - 1
            do t = 0, 7
              corner = [mod(t, 2), mod(t/2, 2), t/4]
              lattice_of(corner(1), corner(2), corner(3)) = node_of(n, i + corner(1), &
                  j + corner(2), k + corner(3))
            end do
            ! odd = parity of the cube's origin; local corner c is globally even when
            ! its bit sum has the parity of odd
            odd = mod(i + j + k, 2)
            e = e + 1
            conn(:, e) = [lattice_of(odd, 0, 0), lattice_of(1 - odd, 1, 0), &
                          lattice_of(1 - odd, 0, 1), lattice_of(odd, 1, 1)]
            ! corner tets at the globally odd corners, with their three neighbours
            do t = 0, 7
              corner = [mod(t, 2), mod(t/2, 2), t/4]
              if (mod(sum(corner) + odd, 2) == 0) cycle
              e = e + 1
              conn(:, e) = [lattice_of(corner(1), corner(2), corner(3)), &
                            lattice_of(1 - corner(1), corner(2), corner(3)), &
                            lattice_of(corner(1), 1 - corner(2), corner(3)), &
                            lattice_of(corner(1), corner(2), 1 - corner(3))]
            end do
          end do
        end do
      end do
      do e = 1, size(conn, 2)
        if (tet_volume(x(:, conn(:, e))) < 0.0_wp) conn(2:3, e) = [conn(3, e), conn(2, e)]
      end do
    else
      allocate(conn(3, 2*n*n))
      e = 0
      do j = 0, n - 1
        do i = 0, n - 1
          a = node_of(n, i, j, 0)
          if (mod(i + j, 2) == 0) then
            conn(:, e + 1) = [a, a + 1, a + n + 2]
            conn(:, e + 2) = [a, a + n + 2, a + n + 1]
          else
            conn(:, e + 1) = [a, a + 1, a + n + 1]
            conn(:, e + 2) = [a + 1, a + n + 2, a + n + 1]
          end if
          e = e + 2
        end do
      end do
    end if
    allocate(part(size(conn, 2)))
    do e = 1, size(conn, 2)
      select case (parts)
      case (PART_MEFEM)
        part(e) = 1
      case (PART_STANDARD)
        part(e) = 2
      case default
        part(e) = merge(1, 2, sum(x(1, conn(:, e)))/size(conn, 1) < 0.5_wp)
      end select
    end do
    call build_model(dim, x, conn, part, model)
  end subroutine make_mesh

  !> Node number of lattice point (i, j, k) of an n-cube mesh.
  pure integer function node_of(n, i, j, k)
    integer, intent(in) :: n, i, j, k             !< cells per direction, position
    node_of = 1 + i + (n + 1)*(j + (n + 1)*k)
  end function node_of

  !> Signed volume of a tetrahedron.
  pure real(wp) function tet_volume(xc)
    real(wp), intent(in) :: xc(:,:)               !< (3, 4) corners
    real(wp) :: a(3), b(3), c(3)
    a = xc(:, 2) - xc(:, 1)
    b = xc(:, 3) - xc(:, 1)
    c = xc(:, 4) - xc(:, 1)
    tet_volume = (a(1)*(b(2)*c(3) - b(3)*c(2)) - a(2)*(b(1)*c(3) - b(3)*c(1)) + &
                  a(3)*(b(1)*c(2) - b(2)*c(1)))/6.0_wp
  end function tet_volume

  !> Signed area of a triangle (x-y plane).
  pure real(wp) function tri_area(xc)
    real(wp), intent(in) :: xc(:,:)               !< (3, 3) corners
    tri_area = 0.5_wp*((xc(1, 2) - xc(1, 1))*(xc(2, 3) - xc(2, 1)) - &
                       (xc(2, 2) - xc(2, 1))*(xc(1, 3) - xc(1, 1)))
  end function tri_area

  !> The slot layout of ME-FEM face cells that the explicit blocks' compact gradients rely
  !> on (mefem_cell_finite_strain, FACE_COMPACT_COLUMNS), on a distorted tet mesh: slots 1-4
  !> and 6 mesh nodes, 5 and 7 enriched; the gradients expanded from the compact ones equal
  !> the built ones to round-off of the cell's largest gradient (G_6 the others' negated
  !> sum, G_7 = -G_5; a boundary cell's 5 nodes as built).
  subroutine check_face_layout()
    type(model_t) :: model
    type(cells_t) :: cells
    type(status_t) :: status
    real(wp) :: grad(3, 7), expanded(3, 7), worst, scale
    integer :: c, nn, faces, boundary
    logical :: slots_ok
    call make_mesh(3, 3, 0.25_wp, PART_MEFEM, model)
    call cells_build(model, cells, status)
    call check(status%ok, 'face layout: cells built')
    if (.not. status%ok) return
    worst = 0.0_wp
    slots_ok = .true.
    faces = 0
    boundary = 0
    do c = 1, cells%n
      nn = cells%nnodes(c)
      if (nn == 7) faces = faces + 1
      if (nn == 5) boundary = boundary + 1
      grad = 0.0_wp
      grad(:, 1:nn) = cells%grad(:, 1:nn, cell_grad_column(cells, c))
      expanded = face_gradients_expanded(nn, face_gradients_compact(grad))
      scale = maxval(abs(grad))
      worst = max(worst, maxval(abs(expanded - grad))/scale)
      slots_ok = slots_ok .and. all(cells%nodes(1:4, c) <= cells%n_mesh_nodes) .and. &
                 cells%nodes(5, c) > cells%n_mesh_nodes
      if (nn == 7) slots_ok = slots_ok .and. cells%nodes(6, c) <= cells%n_mesh_nodes .and. &
                              cells%nodes(7, c) > cells%n_mesh_nodes
    end do
    call check(faces > 0 .and. boundary > 0 .and. faces + boundary == cells%n, &
               'face layout: every ME-FEM cell has 7 (inside) or 5 (boundary) nodes')
    call check(slots_ok, 'face layout: corners in slots 1-4 and 6, enriched nodes in 5 and 7')
    call check(worst <= 1.0e-14_wp, 'face layout: compact gradients expand to the cells'' own '// &
               '(largest difference '//trim(rtoa(worst))//' of the largest gradient)')
  end subroutine check_face_layout

  !> cells_build with elements wanted (the explicit analysis: a rank's own): the same cells,
  !> numbered alike, and the gradients of exactly those whose first element is wanted, equal
  !> to the full build's (mixed ME-FEM and standard parts; every other element wanted).
  subroutine check_kept_gradients(dim, n, jitter)
    integer, intent(in) :: dim, n                         !< dimension, mesh divisions
    real(wp), intent(in) :: jitter                        !< node jitter
    type(model_t) :: model
    type(cells_t) :: full, kept
    type(status_t) :: status
    logical, allocatable :: wanted(:)
    character(len=40) :: what
    integer :: c, e, columns, bad
    write(what, '(a,i0,a)') 'kept gradients, ', dim, 'D'
    call make_mesh(dim, n, jitter, PART_MIXED, model)
    wanted = [(mod(e, 2) == 0, e = 1, model%elements%n)]
    call cells_build(model, full, status)
    call cells_build(model, kept, status, wanted=wanted)
    call check(status%ok, trim(what)//': built')
    if (.not. status%ok) return
    call check_equal(kept%n, full%n, trim(what)//': the same cells')
    call check(all(kept%nodes(:, 1:kept%n) == full%nodes(:, 1:full%n)) .and. &
               all(kept%elements(:, 1:kept%n) == full%elements(:, 1:full%n)), &
               trim(what)//': numbered alike, the same nodes and elements')
    columns = 0
    bad = 0
    do c = 1, kept%n
      if (wanted(kept%elements(1, c))) then
        columns = columns + 1
        if (cell_grad_column(kept, c) /= columns) then
          bad = bad + 1
        else if (any(kept%grad(:, :, columns) /= full%grad(:, :, c))) then
          bad = bad + 1
        end if
      else if (cell_grad_column(kept, c) /= 0) then
        bad = bad + 1
      end if
    end do
    call check(columns > 0 .and. columns < kept%n, trim(what)//': some cells kept, not all')
    call check_equal(bad, 0, trim(what)//': the wanted cells'' gradients, the full build''s')
    call check_equal(size(kept%grad, 3), columns, trim(what)//': no more columns than kept')
  end subroutine check_kept_gradients

  !> Cells, lumped masses, shares and inverse-mass metrics of a model.
  subroutine cell_set_up(model, cells, mass, share, w0, ok)
    type(model_t), intent(in) :: model                    !< model
    type(cells_t), intent(out) :: cells                   !< its cells
    real(wp), allocatable, intent(out) :: mass(:)         !< lumped masses
    real(wp), allocatable, intent(out) :: share(:,:)      !< cell shares
    real(wp), allocatable, intent(out) :: w0(:,:,:)       !< cell metrics
    logical, intent(out) :: ok                            !< cells built
    type(status_t) :: status
    integer :: c
    call cells_build(model, cells, status)
    ok = status%ok
    if (.not. ok) then
      call check(.false., 'cells built', status%message)
      return
    end if
    call lumped_mass(model, cells, .true., mass)
    call cell_mass_shares(model, cells, [(c, c = 1, cells%n)], share)
    call cell_inverse_mass_metric(cells, [(c, c = 1, cells%n)], share, w0)
  end subroutine cell_set_up

  !> The omega^2 bound of every cell at the deformation gradient f.
  function cell_bounds(model, cells, w0, f) result(bound)
    type(model_t), intent(in) :: model                    !< model (materials)
    type(cells_t), intent(in) :: cells                    !< cells
    real(wp), intent(in) :: w0(:,:,:)                     !< cell metrics
    real(wp), intent(in) :: f(3, 3)                       !< deformation gradient
    real(wp) :: bound(cells%n)
    real(wp) :: lambda, mu
    integer :: c
    do c = 1, cells%n
      call material_elastic_moduli(model%materials(cells%material(c)), lambda, mu)
      bound(c) = cell_critical_omega_squared(cells%dim, cells%weight(c), w0(:, :, c), f, &
                                             lambda, mu)
    end do
  end function cell_bounds

  ! ------------------------------------------------------------------ 1 eigenvalues

  !> Closed-form largest eigenvalue against dsyev: random symmetric matrices (entries in
  !> [-0.5, 0.5), diagonal shifted to make some definite), diagonal and isotropic ones, and
  !> matrices whose two largest eigenvalues coincide (the trigonometric formula's worst case).
  subroutine check_eigenvalue_closed_form()
    integer, parameter :: NSAMPLES = 500
    real(wp) :: a(3, 3), w(3), q(3, 3), worst(2), worst_double, scale, got, angle(3)
    integer :: s, n, i, j
    worst = 0.0_wp
    do s = 1, NSAMPLES
      do n = 2, 3
        do j = 1, n
          do i = 1, j
            a(i, j) = hash(s, 10*i + j + 100*n)
            a(j, i) = a(i, j)
          end do
        end do
        do i = 1, n
          a(i, i) = a(i, i) + 0.5_wp*mod(s, 3)
        end do
        call eigenvalues(a(1:n, 1:n), w(1:n))
        scale = maxval(abs(w(1:n)))
        got = symmetric_max_eigenvalue(n, a)
        worst(n - 1) = max(worst(n - 1), abs(got - w(n))/scale)
      end do
    end do
    call info('closed-form lambda_max vs dsyev, random: 2x2 '//real_text(worst(1))// &
              ', 3x3 '//real_text(worst(2))//' (relative to the spectral radius)')
    ! measured 1.1e-16 (2x2) and 8.9e-16 (3x3)
    call check(worst(1) <= 1.0e-14_wp, 'closed-form largest eigenvalue, random 2x2 (1e-14)')
    call check(worst(2) <= 1.0e-14_wp, 'closed-form largest eigenvalue, random 3x3 (1e-14)')
    ! double largest eigenvalue: Q diag(1, 1, 0.3) Q^T with random rotations Q
    worst_double = 0.0_wp
    do s = 1, NSAMPLES
      angle = [(6.0_wp*hash(s, 900 + i), i = 1, 3)]
      q = rotation(angle)
      a = matmul(q, matmul(diagonal([1.0_wp, 1.0_wp, 0.3_wp]), transpose(q)))
      a = 0.5_wp*(a + transpose(a))
      worst_double = max(worst_double, abs(symmetric_max_eigenvalue(3, a) - 1.0_wp))
    end do
    call info('closed-form lambda_max, double top eigenvalue: worst relative error '// &
              real_text(worst_double))
    ! measured 3.2e-8 (the cubic's double root: sqrt of the round-off of its coefficients)
    call check(worst_double <= 1.0e-7_wp, 'closed-form largest eigenvalue, double top '// &
               'eigenvalue (1e-7; irrelevant for a time step)')
    call check_close(symmetric_max_eigenvalue(3, 2.5_wp*IDENTITY), 2.5_wp, 1.0e-15_wp, &
                     'closed-form largest eigenvalue of 2.5 I')
    call check_close(symmetric_max_eigenvalue(3, diagonal([0.2_wp, 3.0_wp, -4.0_wp])), 3.0_wp, &
                     1.0e-15_wp, 'closed-form largest eigenvalue of diag(0.2, 3, -4)')
    call check_close(symmetric_max_eigenvalue(2, diagonal([0.2_wp, -4.0_wp, 9.0_wp])), &
                     0.2_wp, 1.0e-15_wp, 'closed-form largest eigenvalue, 2x2 block only')
  end subroutine check_eigenvalue_closed_form

  !> Diagonal matrix.
  pure function diagonal(d) result(m)
    real(wp), intent(in) :: d(3)                  !< diagonal
    real(wp) :: m(3, 3)
    integer :: i
    m = 0.0_wp
    do i = 1, 3
      m(i, i) = d(i)
    end do
  end function diagonal

  !> Rotation R_z(a3) R_y(a2) R_x(a1).
  pure function rotation(angle) result(r)
    real(wp), intent(in) :: angle(3)              !< angles
    real(wp) :: r(3, 3), rx(3, 3), ry(3, 3), rz(3, 3)
    real(wp) :: c(3), s(3)
    c = cos(angle)
    s = sin(angle)
    rx = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, c(1), s(1), 0.0_wp, -s(1), c(1)], [3, 3])
    ry = reshape([c(2), 0.0_wp, -s(2), 0.0_wp, 1.0_wp, 0.0_wp, s(2), 0.0_wp, c(2)], [3, 3])
    rz = reshape([c(3), s(3), 0.0_wp, -s(3), c(3), 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
    r = matmul(rz, matmul(ry, rx))
  end function rotation

  !> Short text of a real.
  function real_text(x) result(text)
    real(wp), intent(in) :: x                     !< value
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(es10.3)') x
    text = trim(adjustl(buffer))
  end function real_text

  ! ------------------------------------------------------------------ 2 material moduli

  !> lambda and mu of every elastic kind against its tangent at F = I (c_1122 = lambda,
  !> c_1212 = mu, c_1111 = lambda + 2 mu); zero for rigid.
  subroutine check_material_moduli()
    type(material_t) :: mat, blank
    type(curve_t), allocatable :: curves(:)
    real(wp) :: lambda, mu, hist_old(NHIST), hist_new(NHIST), tau(3, 3), c(3, 3, 3, 3), speed
    type(status_t) :: status
    integer :: kind
    character(len=16) :: name
    allocate(curves(0))
    call material_state_init(hist_old)
    do kind = 1, 4
      mat = blank
      mat%id = kind
      mat%density = 7.85e-9_wp
      mat%young = 210000.0_wp
      mat%poisson = 0.3_wp
      select case (kind)
      case (1)
        mat%kind = MAT_ELASTIC
        name = 'elastic'
      case (2)
        mat%kind = MAT_PIECEWISE_LINEAR
        mat%yield_stress = 250.0_wp
        mat%tangent_modulus = 2000.0_wp
        name = 'MAT_024'
      case (3)
        mat%kind = MAT_POWER_LAW
        mat%k_strength = 530.0_wp
        mat%n_exponent = 0.26_wp
        mat%yield_stress = 250.0_wp
        name = 'MAT_018'
      case default
        mat%kind = MAT_MOONEY_RIVLIN
        mat%mr_a = 0.4_wp
        mat%mr_b = 0.1_wp
        mat%poisson = 0.49_wp
        mat%young = 0.0_wp                  ! must not be used for *MAT_027
        name = 'Mooney-Rivlin'
      end select
      call material_elastic_moduli(mat, lambda, mu)
      call material_update(mat, curves, IDENTITY, hist_old, hist_new, tau, c, speed, status)
      call check(status%ok, trim(name)//': update at F = I')
      call check_close(lambda, c(1, 1, 2, 2), 1.0e-12_wp, trim(name)//': lambda = c_1122(F=I)')
      call check_close(mu, c(1, 2, 1, 2), 1.0e-12_wp, trim(name)//': mu = c_1212(F=I)')
      call check_close(lambda + 2.0_wp*mu, c(1, 1, 1, 1), 1.0e-12_wp, &
                       trim(name)//': lambda + 2 mu = c_1111(F=I)')
    end do
    call check_close(mu, 1.0_wp, 1.0e-15_wp, 'Mooney-Rivlin: mu = 2 (A + B)')
    mat = blank
    mat%kind = MAT_RIGID
    mat%young = 1.0_wp
    call material_elastic_moduli(mat, lambda, mu)
    call check(lambda == 0.0_wp .and. mu == 0.0_wp, 'rigid: no elastic moduli')
  end subroutine check_material_moduli

  ! ------------------------------------------------------------------ 3 regular simplex

  !> One standard element, equilateral triangle of edge L (plane strain) or regular
  !> tetrahedron: W is isotropic, so the bound is exact; closed forms with the altitude H:
  !> 2D omega^2 = 9 (lambda + mu)/(rho H^2), 3D omega^2 = 16 (3 lambda + 2 mu)/(3 rho H^2)
  !> (g_I = n_I/H, sum n n^T = (dim+1)/dim I over the unit side normals, m = rho V/(dim+1)).
  subroutine check_regular_simplex(dim)
    integer, intent(in) :: dim                    !< 2 or 3
    real(wp), parameter :: EDGE = 0.7_wp
    real(wp), parameter :: POISSONS(3) = [0.3_wp, -0.3_wp, 0.49_wp]
    type(model_t) :: model
    type(cells_t) :: cells
    real(wp), allocatable :: x(:,:), mass(:), share(:,:), bound(:), w0(:,:,:)
    real(wp) :: lambda, mu, exact, altitude, closed, rho
    integer :: conn(dim + 1, 1), part(1), k
    logical :: ok
    character(len=40) :: tag
    if (dim == 2) then
      x = reshape([0.0_wp, 0.0_wp, 0.0_wp, EDGE, 0.0_wp, 0.0_wp, &
                   0.5_wp*EDGE, 0.5_wp*sqrt(3.0_wp)*EDGE, 0.0_wp], [3, 3])
      altitude = 0.5_wp*sqrt(3.0_wp)*EDGE
    else
      ! alternate corners of a cube of side EDGE/sqrt(2)
      x = EDGE/sqrt(8.0_wp)*reshape([1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp, -1.0_wp, &
          -1.0_wp, 1.0_wp, -1.0_wp, -1.0_wp, -1.0_wp, 1.0_wp], [3, 4])
      altitude = sqrt(2.0_wp/3.0_wp)*EDGE
    end if
    conn(:, 1) = [(k, k = 1, dim + 1)]
    if (dim == 3) then
      if (tet_volume(x) < 0.0_wp) conn(2:3, 1) = [3, 2]
    end if
    part = PART_STANDARD
    do k = 1, size(POISSONS)
      call build_model(dim, x, conn, part, model)
      model%materials(2)%poisson = POISSONS(k)
      call cell_set_up(model, cells, mass, share, w0, ok)
      if (.not. ok) return
      bound = cell_bounds(model, cells, w0, IDENTITY)
      call material_elastic_moduli(model%materials(2), lambda, mu)
      exact = cell_exact_omega_squared(dim, dim + 1, cells%grad(:, :, 1), cells%weight(1), &
                                       share(:, 1), lambda, mu)
      rho = model%materials(2)%density
      if (dim == 2) then
        closed = (2.0_wp*max(lambda, 0.0_wp) + 2.0_wp*mu)*4.5_wp/(rho*altitude**2)
      else
        closed = (3.0_wp*max(lambda, 0.0_wp) + 2.0_wp*mu)*16.0_wp/(3.0_wp*rho*altitude**2)
      end if
      write(tag, '(a,i0,a,f5.2)') 'regular simplex ', dim, 'D nu=', POISSONS(k)
      call check_close(bound(1), exact, 1.0e-10_wp, trim(tag)//': bound = exact lambda_max(K,M)')
      call check_close(bound(1), closed, 1.0e-12_wp, trim(tag)//': bound = closed form')
    end do
  end subroutine check_regular_simplex

  ! ------------------------------------------------------------------ 4 meshes

  !> Shares, per-cell bounds against the exact cell eigenvalues, the global eigenvalue and
  !> the current-configuration formula on one mesh. ratio_limit bounds
  !> max cell bound / lambda_max(M^-1 K) with the stiffness-weighted mass split the explicit
  !> solver uses; measured (omega^2, doc/theory.md 7), equal split -> weighted split:
  !>   tet 5-cube ME-FEM 2.04 -> 1.89, standard 1.57 -> 1.47, distorted ME-FEM 7.47 -> 2.83,
  !>   distorted standard 10.4 -> 2.92, mixed 2.09 -> 2.11; tri distorted ME-FEM 3.79 ->
  !>   2.17, distorted standard 6.88 -> 2.38, regular mixed 2.51 -> 2.67.
  !> The per-cell formula is within 8% of the exact cell eigenvalue (exact/bound >= 0.92);
  !> the rest is the element-eigenvalue theorem itself (max exact cell / global), large on
  !> distorted meshes with the equal split: the worst cell is a small element whose nodes
  !> carry mostly the mass of larger neighbours (5-12% of it from the element), which the
  !> weighted split gives to the stiff small cell instead. The limits are the measured
  !> values plus about 15% (the equal split fails those of the distorted meshes).
  subroutine check_mesh(name, dim, n, jitter, parts, ratio_limit)
    character(len=*), intent(in) :: name          !< mesh name
    integer, intent(in) :: dim, n                 !< dimension, cells per direction
    real(wp), intent(in) :: jitter                !< node perturbation (0: regular)
    integer, intent(in) :: parts                  !< PART_*
    real(wp), intent(in) :: ratio_limit           !< asserted max bound / global
    type(model_t) :: model
    type(cells_t) :: cells
    real(wp), allocatable :: mass(:), share(:,:), bound(:), summed(:), exact(:), w0(:,:,:)
    real(wp) :: lambda, mu, worst_share, min_measure, global_power, global_exact, f(3, 3)
    integer :: c, j, nall, e
    logical :: ok, ok_slots

    call make_mesh(dim, n, jitter, parts, model)
    min_measure = huge(1.0_wp)
    do e = 1, model%elements%n
      if (dim == 3) then
        min_measure = min(min_measure, tet_volume(model%nodes%x(:, model%elements%conn(1:4, e))))
      else
        min_measure = min(min_measure, tri_area(model%nodes%x(:, model%elements%conn(1:3, e))))
      end if
    end do
    call check(min_measure > 0.0_wp, name//': all elements positively oriented')
    call info(name//': smallest altitude / spacing '//real_text(min_altitude(model)*n))
    call cell_set_up(model, cells, mass, share, w0, ok)
    if (.not. ok) return
    bound = cell_bounds(model, cells, w0, IDENTITY)
    nall = cells%n_mesh_nodes + cells%n_enriched

    ! shares: positive in the used slots, zero beyond; sum = lumped mass
    ok_slots = .true.
    allocate(summed(nall))
    summed = 0.0_wp
    do c = 1, cells%n
      ok_slots = ok_slots .and. all(share(1:cells%nnodes(c), c) > 0.0_wp) .and. &
                 all(share(cells%nnodes(c) + 1:CELL_MAX_NODES, c) == 0.0_wp)
      do j = 1, cells%nnodes(c)
        summed(cells%nodes(j, c)) = summed(cells%nodes(j, c)) + share(j, c)
      end do
    end do
    call check(ok_slots, name//': shares positive at every cell node, zero elsewhere')
    ! a rank's own cells (here every third, backwards): the same bits as from all cells
    block
      integer, allocatable :: list(:)
      real(wp), allocatable :: share_part(:,:), w0_part(:,:,:)
      list = [(c, c = cells%n, 1, -3)]
      call cell_mass_shares(model, cells, list, share_part)
      call cell_inverse_mass_metric(cells, list, share_part, w0_part)
      call check(all(share_part == share(:, list)) .and. all(w0_part == w0(:, :, list)), &
                 name//': shares and metrics of a list of cells = those of all cells (bits)')
    end block
    worst_share = maxval(abs(summed - mass)/mass)
    call check(worst_share <= 1.0e-14_wp, name//': shares sum to lumped_mass (1e-14)', &
               'worst '//real_text(worst_share))

    ! per cell: bound >= exact largest eigenvalue of (K_c, M_c)
    allocate(exact(cells%n))
    do c = 1, cells%n
      call material_elastic_moduli(model%materials(cells%material(c)), lambda, mu)
      exact(c) = cell_exact_omega_squared(dim, cells%nnodes(c), cells%grad(:, :, c), &
                                          cells%weight(c), share(:, c), lambda, mu)
    end do
    call check(all(exact <= bound*(1.0_wp + 1.0e-12_wp)), name// &
               ': every cell bound >= exact lambda_max(K_c, M_c)', &
               'worst exact/bound '//real_text(maxval(exact/bound)))
    ! the cruder modulus (dim lambda + 2 mu) lambda_max(W) gives 0.55 on ME-FEM cells
    call check(minval(exact/bound) >= 0.85_wp, name//': every cell bound <= exact / 0.85 '// &
               '(measured >= 0.92)', 'min exact/bound '//real_text(minval(exact/bound)))
    call info(name//': cells '//int_text(cells%n)//', shares vs lumped mass '// &
              real_text(worst_share)//', exact/bound per cell in ['// &
              real_text(minval(exact/bound))//', '//real_text(maxval(exact/bound))//']')

    ! global lambda_max(M^-1 K): power iteration and dsyev
    call global_eigenvalue(name, model, cells, mass, global_power, global_exact)
    ! the Rayleigh quotient is a lower bound; regular meshes have clustered top eigenvalues
    ! and converge slowly: worst measured 1.5e-5 after 3000 iterations (tri regular mixed)
    call check(global_power <= global_exact*(1.0_wp + 1.0e-12_wp) .and. &
               global_power >= global_exact*(1.0_wp - 1.0e-4_wp), name// &
               ': power iteration = dsyev lambda_max(M^-1 K) (1e-4, from below)', &
               real_text(global_power)//' vs '//real_text(global_exact))
    call check(global_exact <= maxval(bound)*(1.0_wp + 1.0e-12_wp), name// &
               ': lambda_max(M^-1 K) <= max cell bound (stable step is safe)')
    call info(name//': dofs '//int_text(dim*nall)//', max bound / global omega^2 = '// &
              real_text(maxval(bound)/global_exact)//', max exact cell / global = '// &
              real_text(maxval(exact)/global_exact)//', dt ratio = '// &
              real_text(sqrt(global_exact/maxval(bound))))

    ! the stiffness-weighted split (the explicit solver's): safe, and closer to the global
    ! eigenvalue than the equal split
    block
      real(wp), allocatable :: weights(:,:), share_w(:,:), w0_w(:,:,:), bound_w(:)
      real(wp) :: worst_w
      allocate(weights(CELL_MAX_NODES, cells%n), share_w(CELL_MAX_NODES, cells%n), &
               w0_w(dim, dim, cells%n))
      weights = 0.0_wp
      do c = 1, cells%n
        call cell_split_weights(dim, cells%nnodes(c), cells%weight(c), cells%grad(:, :, c), &
                                IDENTITY, weights(:, c))
      end do
      call split_by_weights(cells, mass, weights, share_w, w0_w, summed)
      worst_w = maxval(abs(summed - mass)/mass)
      call check(worst_w <= 1.0e-14_wp, name//': weighted shares sum to lumped_mass (1e-14)', &
                 'worst '//real_text(worst_w))
      bound_w = cell_bounds(model, cells, w0_w, IDENTITY)
      call check(global_exact <= maxval(bound_w)*(1.0_wp + 1.0e-12_wp), name// &
                 ': lambda_max(M^-1 K) <= max cell bound, weighted split (safe)')
      call check(maxval(bound_w) <= ratio_limit*global_exact, name// &
                 ': max cell bound / lambda_max(M^-1 K), weighted split, <= '// &
                 real_text(ratio_limit), real_text(maxval(bound_w)/global_exact))
      call info(name//': weighted split: max bound / global omega^2 = '// &
                real_text(maxval(bound_w)/global_exact)//', dt ratio = '// &
                real_text(sqrt(global_exact/maxval(bound_w))))
      ! the explicit solver's rebalancing passes (cell_rebalance_weights, SPLIT_PASSES = 4):
      ! still a split (safe), and a lower largest bound than the weighted split's
      block
        real(wp), allocatable :: bound_p(:)
        integer :: pass
        do pass = 1, 4
          do c = 1, cells%n
            call material_elastic_moduli(model%materials(cells%material(c)), lambda, mu)
            call cell_rebalance_weights(dim, cells%nnodes(c), cells%weight(c), &
                                        cells%grad(:, :, c), share_w(:, c), IDENTITY, lambda, &
                                        mu, weights(:, c))
          end do
          call split_by_weights(cells, mass, weights, share_w, w0_w, summed)
        end do
        worst_w = maxval(abs(summed - mass)/mass)
        call check(worst_w <= 1.0e-14_wp .and. all(share_w >= 0.0_wp), name// &
                   ': rebalanced shares sum to lumped_mass (1e-14)', 'worst '//real_text(worst_w))
        bound_p = cell_bounds(model, cells, w0_w, IDENTITY)
        call check(global_exact <= maxval(bound_p)*(1.0_wp + 1.0e-12_wp), name// &
                   ': lambda_max(M^-1 K) <= max cell bound, rebalanced split (safe)')
        call check(maxval(bound_p) <= maxval(bound_w), name// &
                   ': 4 rebalancing passes lower the largest cell bound', &
                   real_text(maxval(bound_p)/maxval(bound_w)))
        call info(name//': rebalanced split: max bound / global omega^2 = '// &
                  real_text(maxval(bound_p)/global_exact)//', dt ratio = '// &
                  real_text(sqrt(global_exact/maxval(bound_p))))
      end block
    end block

    ! current configuration: bound at F = bound of the cells rebuilt at x = F X
    f = merge(F_3D, F_2D, dim == 3)
    call check_deformed(name, model, cells, cell_bounds(model, cells, w0, f), f)
  end subroutine check_mesh

  !> Each node's mass shared among its cells by the weights (share = m w / sum of w at the
  !> node), the cells' inverse-mass metrics, and the shares summed back at the nodes.
  subroutine split_by_weights(cells, mass, weights, share, w0, summed)
    type(cells_t), intent(in) :: cells              !< cells
    real(wp), intent(in) :: mass(:)                 !< lumped masses of all nodes
    real(wp), intent(in) :: weights(:,:)            !< (CELL_MAX_NODES, cells) split weights
    real(wp), intent(out) :: share(:,:)             !< (CELL_MAX_NODES, cells) mass shares
    real(wp), intent(out) :: w0(:,:,:)              !< (dim, dim, cells) metrics
    real(wp), intent(out) :: summed(:)              !< shares summed at the nodes
    real(wp) :: sums(size(mass))
    integer :: c, j
    sums = 0.0_wp
    do c = 1, cells%n
      do j = 1, cells%nnodes(c)
        sums(cells%nodes(j, c)) = sums(cells%nodes(j, c)) + weights(j, c)
      end do
    end do
    share = 0.0_wp
    summed = 0.0_wp
    do c = 1, cells%n
      do j = 1, cells%nnodes(c)
        share(j, c) = mass(cells%nodes(j, c))*weights(j, c)/sums(cells%nodes(j, c))
        summed(cells%nodes(j, c)) = summed(cells%nodes(j, c)) + share(j, c)
      end do
      call inverse_mass_metric(cells%dim, cells%nnodes(c), cells%grad(:, :, c), share(:, c), &
                               w0(:, :, c))
    end do
  end subroutine split_by_weights

  !> Smallest altitude of the model's elements.
  real(wp) function min_altitude(model)
    type(model_t), intent(in) :: model            !< model
    real(wp) :: xc(3, 4), altitude, face(3), measure
    integer :: e, k, nv, dim
    dim = model%dimension
    nv = dim + 1
    min_altitude = huge(1.0_wp)
    do e = 1, model%elements%n
      xc(:, 1:nv) = model%nodes%x(:, model%elements%conn(1:nv, e))
      if (dim == 3) then
        measure = abs(tet_volume(xc))
        do k = 1, 4
          ! face opposite corner k: area from the cross product of two of its edges
          face = cross3(xc(:, mod(k, 4) + 1) - xc(:, mod(k + 1, 4) + 1), &
                        xc(:, mod(k + 2, 4) + 1) - xc(:, mod(k + 1, 4) + 1))
          altitude = 3.0_wp*measure/(0.5_wp*norm2(face))
          min_altitude = min(min_altitude, altitude)
        end do
      else
        measure = abs(tri_area(xc))
        do k = 1, 3
          altitude = 2.0_wp*measure/norm2(xc(:, mod(k, 3) + 1) - xc(:, mod(k + 1, 3) + 1))
          min_altitude = min(min_altitude, altitude)
        end do
      end if
    end do
  end function min_altitude

  !> Cross product.
  pure function cross3(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)            !< vectors
    real(wp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross3

  !> Integer as text.
  function int_text(i) result(text)
    integer, intent(in) :: i                      !< value
    character(len=:), allocatable :: text
    character(len=16) :: buffer
    write(buffer, '(i0)') i
    text = trim(buffer)
  end function int_text

  !> lambda_max(M^-1 K) of the whole model (free, small strain): dense K assembled from the
  !> cells, S = M^-1/2 K M^-1/2; power iteration (Rayleigh quotient) and dsyev.
  subroutine global_eigenvalue(name, model, cells, mass, by_power, by_dsyev)
    character(len=*), intent(in) :: name          !< mesh name
    type(model_t), intent(in) :: model            !< model
    type(cells_t), intent(in) :: cells            !< cells
    real(wp), intent(in) :: mass(:)               !< lumped masses
    real(wp), intent(out) :: by_power, by_dsyev   !< the two estimates
    integer, parameter :: MAX_ITERATIONS = 3000, SHIFT_AFTER = 20
    real(wp), parameter :: TOLERANCE = 1.0e-11_wp  !< relative change of the Rayleigh quotient
    real(wp), allocatable :: s(:,:), k_cell(:,:), scale(:), v(:), w(:), eig(:)
    real(wp) :: lambda, mu, previous, shift
    integer :: dim, ndof, c, a, b, i, k, nn, ia, ib, iteration
    dim = cells%dim
    ndof = dim*size(mass)
    allocate(s(ndof, ndof), scale(ndof))
    s = 0.0_wp
    do c = 1, cells%n
      nn = cells%nnodes(c)
      allocate(k_cell(dim*nn, dim*nn))
      call material_elastic_moduli(model%materials(cells%material(c)), lambda, mu)
      call dense_cell_stiffness(dim, nn, cells%grad(:, :, c), cells%weight(c), lambda, mu, &
                                k_cell)
      do b = 1, nn
        do k = 1, dim
          ib = dim*(cells%nodes(b, c) - 1) + k
          do a = 1, nn
            do i = 1, dim
              ia = dim*(cells%nodes(a, c) - 1) + i
              s(ia, ib) = s(ia, ib) + k_cell(dim*(a - 1) + i, dim*(b - 1) + k)
            end do
          end do
        end do
      end do
      deallocate(k_cell)
    end do
    do a = 1, size(mass)
      scale(dim*(a - 1) + 1:dim*a) = 1.0_wp/sqrt(mass(a))
    end do
    do i = 1, ndof
      s(:, i) = s(:, i)*scale*scale(i)
    end do
    ! power iteration from a pseudo-random start; after SHIFT_AFTER iterations on S - sigma I
    ! with sigma = half the current Rayleigh quotient (< lambda_max/2, so the spectrum
    ! [-sigma, lambda_max - sigma] keeps lambda_max dominant; about twice as fast)
    v = [(hash(i, 7), i = 1, ndof)]
    v = v/norm2(v)
    by_power = 0.0_wp
    shift = 0.0_wp
    do iteration = 1, MAX_ITERATIONS
      if (iteration == SHIFT_AFTER) shift = 0.5_wp*by_power
      w = matmul(s, v) - shift*v
      previous = by_power
      by_power = dot_product(v, w) + shift
      v = w/norm2(w)
      if (abs(by_power - previous) <= TOLERANCE*by_power) exit
    end do
    allocate(eig(ndof))
    call eigenvalues(s, eig)
    by_dsyev = eig(ndof)
    call info(name//': power iteration: '//int_text(min(iteration, MAX_ITERATIONS))// &
              ' iterations, '//int_text(ndof)//' dofs, relative difference to dsyev '// &
              real_text(abs(by_power/by_dsyev - 1.0_wp)))
  end subroutine global_eigenvalue

  !> Bounds at the homogeneous deformation f equal those of the cells rebuilt in the
  !> deformed geometry with density rho/J (same nodal masses) at F = I.
  subroutine check_deformed(name, model, cells, bound_f, f)
    character(len=*), intent(in) :: name          !< mesh name
    type(model_t), intent(in) :: model            !< reference model
    type(cells_t), intent(in) :: cells            !< its cells
    real(wp), intent(in) :: bound_f(:)            !< their bounds at f
    real(wp), intent(in) :: f(3, 3)               !< deformation gradient
    type(model_t) :: deformed
    type(cells_t) :: cells_deformed
    real(wp), allocatable :: mass(:), share(:,:), w0(:,:,:), bound_rebuilt(:)
    real(wp) :: j
    logical :: ok
    j = f(1, 1)*(f(2, 2)*f(3, 3) - f(2, 3)*f(3, 2)) - f(1, 2)*(f(2, 1)*f(3, 3) - &
        f(2, 3)*f(3, 1)) + f(1, 3)*(f(2, 1)*f(3, 2) - f(2, 2)*f(3, 1))
    deformed = model
    deformed%nodes%x = matmul(f, model%nodes%x)
    deformed%materials%density = model%materials%density/j
    call cell_set_up(deformed, cells_deformed, mass, share, w0, ok)
    if (.not. ok) return
    bound_rebuilt = cell_bounds(deformed, cells_deformed, w0, IDENTITY)
    call check(cells_deformed%n == cells%n, name//': deformed mesh has the same cells')
    if (cells_deformed%n /= cells%n) return
    call check(all(cells_deformed%nodes == cells%nodes), name//': ... with the same nodes')
    call check(maxval(abs(bound_f - bound_rebuilt)/bound_rebuilt) <= 1.0e-10_wp, name// &
               ': bound at homogeneous F = bound of the cells rebuilt at x = F X (1e-10)', &
               'worst '//real_text(maxval(abs(bound_f - bound_rebuilt)/bound_rebuilt)))
    call info(name//': current configuration, worst relative difference '// &
              real_text(maxval(abs(bound_f - bound_rebuilt)/bound_rebuilt)))
  end subroutine check_deformed

end program test_stable_time_step
