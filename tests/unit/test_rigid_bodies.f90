!> Rigid bodies (mefem_rigid_bodies): mass, centre and inertia of boxes of tetrahedra,
!> hexahedra and pentahedra, of thin shell plates and with merged point masses against
!> closed forms; torque-free rotation (angular momentum, kinetic energy, the exact motion of
!> a symmetric top, convergence order); translation under a constant force; prescribed
!> motions (VAD 0/1/2, translations and rotation, birth/death) with their reactions;
!> CON1/CON2 constraints; a 2D body turned by a couple; the errors of rigid_bodies_build.
! ranks: 1
program test_rigid_bodies
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t
  use mefem_model, only: model_t, curve_t, prescribed_motion_t, MAT_RIGID, ELEM_SOLID, &
                         ELEM_SHELL, SECTION_SOLID, SECTION_SHELL, ON_PART, TOPO_TRI3, &
                         TOPO_QUAD4, TOPO_TET4, TOPO_PENTA6, TOPO_HEX8
  use mefem_rigid_bodies, only: rigid_bodies_t, rigid_bodies_build, rigid_bodies_set_velocity, &
                                rigid_bodies_accumulate, rigid_bodies_advance, &
                                rigid_body_point_motion, rigid_bodies_kinetic_energy, &
                                rigid_body_reaction
  use mefem_testing, only: test_start, test_finish, check, check_close
  implicit none

  real(wp), parameter :: PI = 3.14159265358979323846_wp
  !> Tetrahedra of a cube (corners in output order, 5-8 over 1-4): four corners and the
  !> middle one (an other split than the hexahedron's, so the two are independent).
  integer, parameter :: CUBE_TETS(4, 5) = reshape([1, 2, 4, 5,  2, 3, 4, 7,  2, 5, 6, 7, &
                                                   4, 5, 7, 8,  2, 4, 5, 7], [4, 5])
  !> Two wedges of a cube (triangle 1-2-3 over 5-6-7, 1-3-4 over 5-7-8).
  integer, parameter :: CUBE_WEDGES(6, 2) = reshape([1, 2, 3, 5, 6, 7,  1, 3, 4, 5, 7, 8], &
                                                    [6, 2])

  call test_start('rigid_bodies')
  call test_solid_box(TOPO_TET4, [1.0_wp, 1.0_wp, 1.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], &
                      'unit cube tets')
  call test_solid_box(TOPO_TET4, [2.0_wp, 1.0_wp, 1.5_wp], [1.0_wp, -2.0_wp, 0.5_wp], 'box tets')
  call test_solid_box(TOPO_HEX8, [2.0_wp, 1.0_wp, 1.5_wp], [1.0_wp, -2.0_wp, 0.5_wp], 'box hexes')
  call test_solid_box(TOPO_PENTA6, [2.0_wp, 1.0_wp, 1.5_wp], [1.0_wp, -2.0_wp, 0.5_wp], &
                      'box wedges')
  call test_shell_plate(TOPO_QUAD4, .false., 'plate quads x-y')
  call test_shell_plate(TOPO_TRI3, .false., 'plate triangles x-y')
  call test_shell_plate(TOPO_QUAD4, .true., 'plate quads x-z')
  call test_merged_masses()
  call test_accumulate()
  call test_free_rotation()
  call test_symmetric_top()
  call test_constant_force()
  call test_prescribed_translation()
  call test_prescribed_rotation()
  call test_constraints()
  call test_partial_rotation_constraint()
  call test_2d_body()
  call test_build_errors()
  call test_finish()

contains

  ! ------------------------------------------------------------------ models

  !> A model of rigid parts 1..n_parts (density 1, CMO 0, sections of the keyword's kind)
  !> over the given nodes and elements.
  subroutine make_model(model, dim, x, conn, topology, keyword, part, n_parts)
    type(model_t), intent(out) :: model          !< the model
    integer, intent(in) :: dim                   !< 2 or 3
    real(wp), intent(in) :: x(:,:)               !< (3, nnode) coordinates
    integer, intent(in) :: conn(:,:)             !< (nn, nel) corners
    integer, intent(in) :: topology, keyword     !< TOPO_*, ELEM_*
    integer, intent(in) :: part(:)               !< (nel) part of each element
    integer, intent(in) :: n_parts               !< parts
    integer :: i, nel
    model%dimension = dim
    model%nodes%n = size(x, 2)
    model%nodes%x = x
    model%nodes%id = [(i, i = 1, size(x, 2))]
    allocate(model%nodes%tc(size(x, 2)), model%nodes%rc(size(x, 2)))
    model%nodes%tc = 0
    model%nodes%rc = 0
    nel = size(conn, 2)
    model%elements%n = nel
    model%elements%id = [(i, i = 1, nel)]
    model%elements%part = part
    model%elements%part_id = 10*part
    allocate(model%elements%keyword(nel), model%elements%topology(nel), &
             model%elements%conn(8, nel))
    model%elements%keyword = keyword
    model%elements%topology = topology
    model%elements%conn = 0
    model%elements%conn(1:size(conn, 1), :) = conn
    model%n_parts = n_parts
    model%n_sections = n_parts
    model%n_materials = n_parts
    allocate(model%parts(n_parts), model%sections(n_parts), model%materials(n_parts))
    do i = 1, n_parts
      model%parts(i)%id = 10*i
      model%parts(i)%section = i
      model%parts(i)%material = i
      model%sections(i)%kind = merge(SECTION_SOLID, SECTION_SHELL, keyword == ELEM_SOLID)
      model%materials(i)%kind = MAT_RIGID
      model%materials(i)%density = 1.0_wp
    end do
    allocate(model%curves(0), model%motions(0), model%sets(0))
  end subroutine make_model

  !> Append a curve through the points (t, f); returns its index.
  integer function add_curve(model, t, f)
    type(model_t), intent(inout) :: model        !< the model
    real(wp), intent(in) :: t(:), f(:)           !< points
    type(curve_t) :: curve
    curve%id = model%n_curves + 1
    curve%n = size(t)
    curve%t = t
    curve%f = f
    model%curves = [model%curves, curve]
    model%n_curves = model%n_curves + 1
    add_curve = model%n_curves
  end function add_curve

  !> Append a *BOUNDARY_PRESCRIBED_MOTION_RIGID.
  subroutine add_motion(model, part, dof, vad, curve, birth, death)
    type(model_t), intent(inout) :: model        !< the model
    integer, intent(in) :: part, dof, vad, curve !< part index, DOF, VAD, curve index
    real(wp), intent(in), optional :: birth, death   !< active interval
    type(prescribed_motion_t) :: motion
    motion%target_kind = ON_PART
    motion%target = part
    motion%target_id = model%parts(part)%id
    motion%dof = dof
    motion%vad = vad
    motion%curve = curve
    if (present(birth)) motion%birth = birth
    if (present(death)) motion%death = death
    model%motions = [model%motions, motion]
    model%n_motions = model%n_motions + 1
  end subroutine add_motion

  !> Box [0,l] + origin of n(1) x n(2) x n(3) cells: tetrahedra (5 per cell), hexahedra or
  !> wedges (2 per cell), connectivity in output order.
  subroutine make_box(n, l, origin, topology, x, conn)
    integer, intent(in) :: n(3)                  !< cells per direction
    real(wp), intent(in) :: l(3), origin(3)      !< size, lowest corner
    integer, intent(in) :: topology              !< TOPO_TET4, TOPO_HEX8 or TOPO_PENTA6
    real(wp), allocatable, intent(out) :: x(:,:) !< (3, nnode)
    integer, allocatable, intent(out) :: conn(:,:)   !< (nn, nel)
    integer :: i, j, k, e, c(8), t
    allocate(x(3, product(n + 1)))
    do k = 0, n(3)
      do j = 0, n(2)
        do i = 0, n(1)
          x(:, box_node(n, i, j, k)) = origin + l*[real(i, wp)/n(1), real(j, wp)/n(2), &
                                                real(k, wp)/n(3)]
        end do
      end do
    end do
    select case (topology)
    case (TOPO_TET4)
      allocate(conn(4, 5*product(n)))
    case (TOPO_HEX8)
      allocate(conn(8, product(n)))
    case default
      allocate(conn(6, 2*product(n)))
    end select
    e = 0
    do k = 0, n(3) - 1
      do j = 0, n(2) - 1
        do i = 0, n(1) - 1
          c = [box_node(n, i, j, k), box_node(n, i + 1, j, k), box_node(n, i + 1, j + 1, k), &
               box_node(n, i, j + 1, k), box_node(n, i, j, k + 1), box_node(n, i + 1, j, k + 1), &
               box_node(n, i + 1, j + 1, k + 1), box_node(n, i, j + 1, k + 1)]
          select case (topology)
          case (TOPO_TET4)
            do t = 1, 5
              e = e + 1
              conn(:, e) = c(CUBE_TETS(:, t))
            end do
          case (TOPO_HEX8)
            e = e + 1
            conn(:, e) = c
          case default
            do t = 1, 2
              e = e + 1
              conn(:, e) = c(CUBE_WEDGES(:, t))
            end do
          end select
        end do
      end do
    end do
  end subroutine make_box

  !> Node of lattice point (i, j, k) of a box of n(1) x n(2) x n(3) cells.
  pure integer function box_node(n, i, j, k)
    integer, intent(in) :: n(3), i, j, k         !< cells, lattice point
    box_node = (k*(n(2) + 1) + j)*(n(1) + 1) + i + 1
  end function box_node

  !> Rectangle [0,a] x [0,b] (z = 0) of nx x ny quads or 2 nx ny triangles.
  subroutine make_rectangle(nx, ny, a, b, topology, x, conn)
    integer, intent(in) :: nx, ny                !< cells per direction
    real(wp), intent(in) :: a, b                 !< sizes
    integer, intent(in) :: topology              !< TOPO_QUAD4 or TOPO_TRI3
    real(wp), allocatable, intent(out) :: x(:,:) !< (3, nnode)
    integer, allocatable, intent(out) :: conn(:,:)   !< (nn, nel)
    integer :: i, j, e, p
    allocate(x(3, (nx + 1)*(ny + 1)))
    do j = 0, ny
      do i = 0, nx
        x(:, j*(nx + 1) + i + 1) = [a*i/nx, b*j/ny, 0.0_wp]
      end do
    end do
    if (topology == TOPO_QUAD4) then
      allocate(conn(4, nx*ny))
    else
      allocate(conn(3, 2*nx*ny))
    end if
    e = 0
    do j = 0, ny - 1
      do i = 0, nx - 1
        p = j*(nx + 1) + i + 1
        if (topology == TOPO_QUAD4) then
          e = e + 1
          conn(:, e) = [p, p + 1, p + nx + 2, p + nx + 1]
        else
          conn(:, e + 1) = [p, p + 1, p + nx + 2]
          conn(:, e + 2) = [p, p + nx + 2, p + nx + 1]
          e = e + 2
        end if
      end do
    end do
  end subroutine make_rectangle

  ! ------------------------------------------------------------------ mass properties

  !> A box a x b x c of density 7.8: m = rho abc, centre in the middle,
  !> I = m/12 diag(b^2 + c^2, c^2 + a^2, a^2 + b^2).
  subroutine test_solid_box(topology, l, origin, name)
    integer, intent(in) :: topology              !< element kind
    real(wp), intent(in) :: l(3), origin(3)      !< size, corner
    character(len=*), intent(in) :: name         !< label
    real(wp), parameter :: RHO = 7.8_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: mass
    call make_box([2, 2, 2], l, origin, topology, x, conn)
    call make_model(model, 3, x, conn, topology, ELEM_SOLID, ones(size(conn, 2)), 1)
    model%materials(1)%density = RHO
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(status%ok, name//': built')
    mass = RHO*product(l)
    ! measured: differences up to 7e-16 relative (tets, hexes, wedges)
    call check_close(bodies%body(1)%mass, mass, 1.0e-14_wp, name//': mass')
    call check_close(bodies%body(1)%centre0, origin + 0.5_wp*l, 1.0e-14_wp, name//': centre')
    call check_close(diagonal(bodies%body(1)%inertia0), mass/12.0_wp*[l(2)**2 + l(3)**2, &
        l(3)**2 + l(1)**2, l(1)**2 + l(2)**2], 1.0e-13_wp, name//': principal inertia')
    call check_close(off_diagonal(bodies%body(1)%inertia0), [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, &
        name//': products of inertia', atol=1.0e-13_wp*mass*maxval(l)**2)
    call check(all(bodies%node_body == 1), name//': every node in the body')
  end subroutine test_solid_box

  !> A plate a x b of thickness t (shells, T1): m = rho a b t, centre in the middle,
  !> inertia of the thin box: a plate in x-y has m/12 diag(b^2 + t^2, a^2 + t^2, a^2 + b^2);
  !> turned into x-z (rotated by 90 degrees about x): m/12 diag(b^2 + t^2, a^2 + b^2, a^2 + t^2).
  subroutine test_shell_plate(topology, in_xz, name)
    integer, intent(in) :: topology              !< TOPO_QUAD4 or TOPO_TRI3
    logical, intent(in) :: in_xz                 !< plate in the x-z plane
    character(len=*), intent(in) :: name         !< label
    real(wp), parameter :: A = 2.0_wp, B = 1.0_wp, T = 0.05_wp, RHO = 2.7_wp, Z0 = 0.3_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:), y(:)
    integer, allocatable :: conn(:,:)
    real(wp) :: mass, want(3), centre(3)
    call make_rectangle(3, 2, A, B, topology, x, conn)
    x(3, :) = Z0
    centre = [A/2, B/2, Z0]
    if (in_xz) then           ! (x, y, z) -> (x, -z, y)
      y = x(2, :)
      x(2, :) = -x(3, :)
      x(3, :) = y
      centre = [A/2, -Z0, B/2]
    end if
    call make_model(model, 3, x, conn, topology, ELEM_SHELL, ones(size(conn, 2)), 1)
    model%materials(1)%density = RHO
    model%sections(1)%thickness = T
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(status%ok, name//': built')
    mass = RHO*A*B*T
    ! measured: differences up to 3e-16 relative
    call check_close(bodies%body(1)%mass, mass, 1.0e-14_wp, name//': mass')
    call check_close(bodies%body(1)%centre0, centre, 1.0e-14_wp, name//': centre')
    if (in_xz) then
      want = mass/12.0_wp*[B**2 + T**2, A**2 + B**2, A**2 + T**2]
    else
      want = mass/12.0_wp*[B**2 + T**2, A**2 + T**2, A**2 + B**2]
    end if
    call check_close(diagonal(bodies%body(1)%inertia0), want, 1.0e-13_wp, &
                     name//': plate inertia (with thickness term)')
    call check_close(off_diagonal(bodies%body(1)%inertia0), [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, &
        name//': products of inertia', atol=1.0e-13_wp*mass*A**2)
  end subroutine test_shell_plate

  !> Unit cube of tets plus point masses (merged deformable masses) at two corners: total
  !> mass, centre and inertia by the parallel-axis theorem.
  subroutine test_merged_masses()
    real(wp), parameter :: M1 = 0.3_wp, M2 = 0.7_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:), merged(:)
    integer, allocatable :: conn(:,:)
    real(wp) :: total, centre(3), inertia(3, 3), cube_centre(3), p1(3), p2(3)
    integer :: n1, n2
    call make_box([1, 1, 1], [1.0_wp, 1.0_wp, 1.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_TET4, &
                  x, conn)
    call make_model(model, 3, x, conn, TOPO_TET4, ELEM_SOLID, ones(size(conn, 2)), 1)
    n1 = 1                       ! corner (0,0,0)
    n2 = size(x, 2)              ! corner (1,1,1)
    allocate(merged(size(x, 2)))
    merged = 0.0_wp
    merged(n1) = M1
    merged(n2) = M2
    call rigid_bodies_build(model, merged, bodies, status)
    call check(status%ok, 'merged masses: built')
    total = 1.0_wp + M1 + M2
    cube_centre = [0.5_wp, 0.5_wp, 0.5_wp]
    p1 = x(:, n1)
    p2 = x(:, n2)
    centre = (cube_centre + M1*p1 + M2*p2)/total
    inertia = shifted(1.0_wp/6.0_wp*identity3(), 1.0_wp, cube_centre - centre) + &
              shifted(0.0_wp*identity3(), M1, p1 - centre) + &
              shifted(0.0_wp*identity3(), M2, p2 - centre)
    ! measured: 1.3e-16 relative
    call check_close(bodies%body(1)%mass, total, 1.0e-14_wp, 'merged masses: mass')
    call check_close(bodies%body(1)%centre0, centre, 1.0e-14_wp, 'merged masses: centre')
    call check_close(reshape(bodies%body(1)%inertia0, [9]), reshape(inertia, [9]), 1.0e-13_wp, &
                     'merged masses: inertia (parallel axes)', atol=1.0e-14_wp)
  end subroutine test_merged_masses

  !> Resultant force and moment of nodal forces about the centre.
  subroutine test_accumulate()
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: force_sum(3, 1), moment_sum(3, 1), f1(3), f2(3), x1(3), x2(3), c(3)
    call make_box([1, 1, 1], [1.0_wp, 2.0_wp, 3.0_wp], [1.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    call make_model(model, 3, x, conn, TOPO_HEX8, ELEM_SOLID, [1], 1)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    force_sum = 0.0_wp
    moment_sum = 0.0_wp
    f1 = [1.0_wp, -2.0_wp, 0.5_wp]
    f2 = [0.0_wp, 3.0_wp, 1.0_wp]
    x1 = x(:, 2)
    x2 = x(:, 7)
    call rigid_bodies_accumulate(bodies, 1, x1, f1, force_sum, moment_sum)
    call rigid_bodies_accumulate(bodies, 1, x2, f2, force_sum, moment_sum)
    c = [1.5_wp, 1.0_wp, 1.5_wp]
    call check_close(force_sum(:, 1), f1 + f2, 1.0e-15_wp, 'accumulate: force')
    ! moment (x - c) x f written out by components
    call check_close(moment_sum(:, 1), cross3(x1 - c, f1) + cross3(x2 - c, f2), 1.0e-15_wp, &
                     'accumulate: moment about the centre', atol=1.0e-15_wp)
  end subroutine test_accumulate

  ! ------------------------------------------------------------------ free rotation

  !> An asymmetric box (1 x 1.5 x 2.5 of tets) spinning about a non-principal axis, no load:
  !> L exact, kinetic energy and the momentum relation I omega = L to the order of the scheme
  !> (second order: the error ratio between dt and dt/2 is about 4).
  subroutine test_free_rotation()
    real(wp) :: energy_drift(2), relation_error(2), l_error
    integer :: refine
    character(len=120) :: line
    do refine = 1, 2
      call spin(refine, energy_drift(refine), relation_error(refine), l_error)
      ! measured: 0 (L is the variable the scheme integrates)
      call check(l_error <= 1.0e-12_wp, 'free rotation: angular momentum conserved', &
                 'relative change '//real_text(l_error))
    end do
    write(line, '(a,2es10.2,a,2es10.2)') 'energy drift ', energy_drift, '  |I_avg w - L|/|L| ', &
        relation_error
    print '(a)', '  free rotation (dt, dt/2): '//trim(line)
    ! measured: energy drift 5.5e-06 -> 1.4e-06 (ratio 4.0), relation error 9.7e-06 -> 2.4e-06;
    ! with the inertia at t^n (MIDPOINT_CORRECTIONS = 0) 9.6e-03 -> 4.8e-03 (first order)
    call check(energy_drift(1) < 1.0e-5_wp, 'free rotation: kinetic energy kept to 1e-5', &
               real_text(energy_drift(1)))
    call check(energy_drift(1)/energy_drift(2) > 3.5_wp, 'free rotation: energy error of '// &
               'second order', real_text(energy_drift(1)/energy_drift(2)))
    call check(relation_error(1)/relation_error(2) > 3.5_wp, 'free rotation: I omega = L to '// &
               'second order', real_text(relation_error(1)/relation_error(2)))
  end subroutine test_free_rotation

  !> Spin the asymmetric box for 4 s with dt = 0.01/refine.
  subroutine spin(refine, energy_drift, relation_error, l_error)
    integer, intent(in) :: refine                !< dt divisor
    real(wp), intent(out) :: energy_drift        !< max |E - E0|/E0
    real(wp), intent(out) :: relation_error      !< max |I_avg omega - L0|/|L0|
    real(wp), intent(out) :: l_error             !< max |L - L0|/|L0|
    real(wp), parameter :: OMEGA0(3) = [0.4_wp, 1.0_wp, 0.7_wp]
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: zero(3, 1), l0(3), e0, dt, t, i_avg(3, 3)
    integer :: n, steps
    call make_box([1, 1, 2], [1.0_wp, 1.5_wp, 2.5_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_TET4, x, conn)
    call make_model(model, 3, x, conn, TOPO_TET4, ELEM_SOLID, ones(size(conn, 2)), 1)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call rigid_bodies_set_velocity(bodies, 1, [0.0_wp, 0.0_wp, 0.0_wp], OMEGA0)
    l0 = matmul(bodies%body(1)%inertia0, OMEGA0)
    e0 = 0.5_wp*dot_product(OMEGA0, l0)
    zero = 0.0_wp
    dt = 0.01_wp/refine
    steps = 400*refine
    t = 0.0_wp
    energy_drift = 0.0_wp
    relation_error = 0.0_wp
    l_error = 0.0_wp
    do n = 1, steps
      call advance_step(model, bodies, n, t, dt, zero, zero)
      t = t + dt
      associate (body => bodies%body(1))
        energy_drift = max(energy_drift, abs(rigid_bodies_kinetic_energy(bodies) - e0)/e0)
        l_error = max(l_error, norm2(body%angular_momentum - l0)/norm2(l0))
        i_avg = 0.5_wp*(rotate(body%inertia0, body%rotation_old) + &
                        rotate(body%inertia0, body%rotation))
        relation_error = max(relation_error, norm2(matmul(i_avg, body%omega) - l0)/norm2(l0))
      end associate
    end do
  end subroutine spin

  !> Torque-free symmetric top (box 1 x 1 x 2 of hexes, symmetry axis z): exact motion
  !> R(t) = exp(t [L]x/I1) exp(t kappa [e_z]x), kappa = L_z (1/I3 - 1/I1). Error of R after
  !> 5 s for dt and dt/2: second order.
  subroutine test_symmetric_top()
    real(wp), parameter :: OMEGA0(3) = [0.6_wp, -0.3_wp, 1.5_wp], END_TIME = 5.0_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: zero(3, 1), l0(3), dt, t, i1, i3, kappa, exact(3, 3), error(2)
    integer :: n, refine
    character(len=80) :: line
    call make_box([1, 1, 2], [1.0_wp, 1.0_wp, 2.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    call make_model(model, 3, x, conn, TOPO_HEX8, ELEM_SOLID, [1, 1], 1)
    zero = 0.0_wp
    do refine = 1, 2
      call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
      call rigid_bodies_set_velocity(bodies, 1, [0.0_wp, 0.0_wp, 0.0_wp], OMEGA0)
      i1 = bodies%body(1)%inertia0(1, 1)
      i3 = bodies%body(1)%inertia0(3, 3)
      l0 = [i1, i1, i3]*OMEGA0
      kappa = l0(3)*(1.0_wp/i3 - 1.0_wp/i1)
      dt = 0.02_wp/refine
      t = 0.0_wp
      do n = 1, nint(END_TIME/dt)
        call rigid_bodies_advance(model, bodies, t + 0.5_wp*dt, t + dt, &
                                  merge(0.5_wp*dt, dt, n == 1), dt, zero, zero)
        t = t + dt
      end do
      exact = matmul(axis_angle(l0/norm2(l0), norm2(l0)*t/i1), &
                     axis_angle([0.0_wp, 0.0_wp, 1.0_wp], kappa*t))
      error(refine) = maxval(abs(bodies%body(1)%rotation - exact))
    end do
    write(line, '(a,2es10.2)') 'max |R - R_exact| (dt, dt/2): ', error
    print '(a)', '  symmetric top: '//trim(line)
    ! measured: 1.75e-04 and 4.31e-05 (ratio 4.1); with the inertia at t^n (no mid-step
    ! correction) 7.5e-02 and 3.7e-02 (first order)
    call check(error(1) < 5.0e-4_wp, 'symmetric top: rotation after 5 s within 5e-4', &
               real_text(error(1)))
    call check(error(1)/error(2) > 3.5_wp, 'symmetric top: second order in dt', &
               real_text(error(1)/error(2)))
  end subroutine test_symmetric_top

  ! ------------------------------------------------------------------ translation, motions

  !> Constant force from rest plus initial velocity: x = x0 + v0 t + F t^2/(2m) exactly
  !> (first step with dt_avg = dt/2), v^{n+1/2} = v0 + F t^{n+1/2}/m, kinetic energy, point
  !> motion of a node.
  subroutine test_constant_force()
    real(wp), parameter :: FORCE(3) = [3.0_wp, -1.0_wp, 2.0_wp], V0(3) = [0.5_wp, 0.0_wp, -1.0_wp]
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: f(3, 1), zero(3, 1), dt, t, m, u(3), v(3), worst_x, worst_v
    integer :: n
    call make_box([1, 1, 1], [2.0_wp, 1.0_wp, 1.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    call make_model(model, 3, x, conn, TOPO_HEX8, ELEM_SOLID, [1], 1)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call rigid_bodies_set_velocity(bodies, 1, V0, [0.0_wp, 0.0_wp, 0.0_wp])
    m = bodies%body(1)%mass
    f(:, 1) = FORCE
    zero = 0.0_wp
    dt = 1.0e-3_wp
    t = 0.0_wp
    worst_x = 0.0_wp
    worst_v = 0.0_wp
    do n = 1, 500
      call advance_step(model, bodies, n, t, dt, f, zero)
      worst_v = max(worst_v, maxval(abs(bodies%body(1)%velocity - (V0 + FORCE*(t + 0.5_wp*dt)/m))))
      t = t + dt
      worst_x = max(worst_x, maxval(abs(bodies%body(1)%centre - &
                    ([1.0_wp, 0.5_wp, 0.5_wp] + V0*t + FORCE*t**2/(2.0_wp*m)))))
    end do
    ! measured: 7.5e-15 and 1.8e-14 (round-off of the sums over 500 steps)
    call check(worst_x < 1.0e-13_wp, 'constant force: x = x0 + v0 t + F t^2/2m', real_text(worst_x))
    call check(worst_v < 1.0e-13_wp, 'constant force: v = v0 + F t/m at half steps', &
               real_text(worst_v))
    call check_close(rigid_bodies_kinetic_energy(bodies), &
                     0.5_wp*m*sum((V0 + FORCE*(t - 0.5_wp*dt)/m)**2), &
                     1.0e-13_wp, 'constant force: kinetic energy')
    call rigid_body_point_motion(bodies, 1, x(:, 7), u, v)
    call check_close(u, V0*t + FORCE*t**2/(2.0_wp*m), 1.0e-12_wp, &
                     'constant force: node displacement')
    call check_close(v, bodies%body(1)%velocity, 1.0e-11_wp, 'constant force: node velocity')
    call check(all(bodies%body(1)%reaction_force == 0.0_wp) .and. &
               all(bodies%body(1)%reaction_moment == 0.0_wp), 'constant force: no reaction')
  end subroutine test_constant_force

  !> Prescribed translations with an applied force F = (Fx, Fy, Fz): x velocity v = c t
  !> (VAD 0) followed exactly, reaction m c - Fx; y acceleration a0 (VAD 1): v = a0 t,
  !> reaction m a0 - Fy; z displacement d = d1 t (VAD 2), reaction -Fz after the first
  !> step. A second body: y velocity 5 between birth 0.1 and death 0.2, free otherwise.
  subroutine test_prescribed_translation()
    real(wp), parameter :: C = 2.0_wp, A0 = -3.0_wp, D1 = 0.25_wp
    real(wp), parameter :: FORCE(3) = [1.0_wp, 4.0_wp, -2.0_wp]
    real(wp), parameter :: V_WINDOW = 5.0_wp, BIRTH = 0.1_wp, DEATH = 0.2_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:), x2(:,:)
    integer, allocatable :: conn(:,:), conn2(:,:)
    real(wp) :: f(3, 2), zero(3, 2), dt, t, m, worst_v(3), worst_r(3), worst_d, rf(3), rm(3)
    real(wp) :: v_before_birth, v_inside, v_after_death, v_old(3), applied_work
    integer :: n, steps
    call make_box([1, 1, 1], [1.0_wp, 1.0_wp, 1.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    call make_box([1, 1, 1], [1.0_wp, 1.0_wp, 1.0_wp], [3.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, &
                  x2, conn2)
    call make_model(model, 3, reshape([x, x2], [3, 16]), reshape([conn, conn2 + 8], [8, 2]), &
                    TOPO_HEX8, ELEM_SOLID, [1, 2], 2)
    call add_motion(model, 1, 1, 0, add_curve(model, [0.0_wp, 10.0_wp], [0.0_wp, 10.0_wp*C]))
    call add_motion(model, 1, 2, 1, add_curve(model, [0.0_wp], [A0]))
    call add_motion(model, 1, 3, 2, add_curve(model, [0.0_wp, 1.0_wp], [0.0_wp, D1]))
    call add_motion(model, 2, 2, 0, add_curve(model, [0.0_wp], [V_WINDOW]), BIRTH, DEATH)
    call rigid_bodies_build(model, zeros(16), bodies, status)
    call check(status%ok, 'prescribed translation: built')
    m = bodies%body(1)%mass
    f(:, 1) = FORCE
    f(:, 2) = 0.0_wp
    zero = 0.0_wp
    dt = 1.0e-3_wp
    steps = 300
    t = 0.0_wp
    worst_v = 0.0_wp
    worst_r = 0.0_wp
    worst_d = 0.0_wp
    applied_work = 0.0_wp
    do n = 1, steps
      v_old = bodies%body(1)%velocity
      call advance_step(model, bodies, n, t, dt, f, zero)
      associate (body => bodies%body(1))
        applied_work = applied_work + merge(0.5_wp*dt, dt, n == 1)* &
                       dot_product(FORCE, 0.5_wp*(v_old + body%velocity))
        worst_v(1) = max(worst_v(1), abs(body%velocity(1) - C*(t + 0.5_wp*dt)))
        worst_v(2) = max(worst_v(2), abs(body%velocity(2) - A0*(t + 0.5_wp*dt)))
        worst_v(3) = max(worst_v(3), abs(body%velocity(3) - D1))
        call rigid_body_reaction(bodies, 1, rf, rm)
        worst_r(1) = max(worst_r(1), abs(rf(1) - (m*C - FORCE(1))))
        worst_r(2) = max(worst_r(2), abs(rf(2) - (m*A0 - FORCE(2))))
        if (n > 1) worst_r(3) = max(worst_r(3), abs(rf(3) + FORCE(3)))
        t = t + dt
        worst_d = max(worst_d, abs(body%centre(3) - body%centre0(3) - D1*t))
      end associate
      if (n == 50) v_before_birth = bodies%body(2)%velocity(2)
      if (n == 150) v_inside = bodies%body(2)%velocity(2)
      if (n == 250) v_after_death = bodies%body(2)%velocity(2)
    end do
    ! Round-off: eps |v| m/dt_avg (1e-13 here) in the reactions; VAD 2 differences positions:
    ! eps |x|/dt in v, eps |x| m/dt^2 (2.2e-10) in the reaction. Measured: velocities 0,
    ! 1.1e-16, 5.5e-14; reactions 5.7e-14 (x, y), 8.4e-11 (z); z displacement 5.5e-17
    call check_close(worst_v(1:2), [0.0_wp, 0.0_wp], 0.0_wp, &
                     'prescribed translation: velocities (VAD 0, 1) followed', atol=1.0e-14_wp)
    call check(worst_v(3) < 1.0e-12_wp, 'prescribed translation: velocity (VAD 2) followed', &
               real_text(worst_v(3)))
    call check_close(worst_r(1:2), [0.0_wp, 0.0_wp], 0.0_wp, &
                     'prescribed translation: reactions m a - F (VAD 0, 1)', atol=1.0e-12_wp)
    call check(worst_r(3) < 1.0e-9_wp, 'prescribed translation: reaction -F (VAD 2)', &
               real_text(worst_r(3)))
    call check(worst_d < 1.0e-14_wp, 'prescribed translation: displacement curve (VAD 2)', &
               real_text(worst_d))
    call check_close(bodies%body(1)%centre(1) - bodies%body(1)%centre0(1), 0.5_wp*C*t**2, &
                     1.0e-12_wp, 'prescribed translation: x = c t^2/2')
    ! kinetic energy from rest = work of the applied force + work of the reactions
    ! (measured: equal to the last bit here)
    call check_close(0.5_wp*m*dot_product(bodies%body(1)%velocity, bodies%body(1)%velocity), &
                     applied_work + bodies%body(1)%reaction_work, 1.0e-12_wp, &
                     'prescribed translation: energy balance with the reaction work')
    call check(v_before_birth == 0.0_wp, 'prescribed translation: inactive before birth')
    call check(v_inside == V_WINDOW, 'prescribed translation: active between birth and death')
    call check(v_after_death == V_WINDOW, 'prescribed translation: free after death (keeps v)')
  end subroutine test_prescribed_translation

  !> Rotation about z prescribed: DOF 7 VAD 0 omega = beta (body 1), DOF 7 VAD 2 angle
  !> theta = beta t (body 2): R = Rz(beta t); with an applied moment M_z the reaction is
  !> -M_z; point velocities are secant velocities (u^{n+1} - u^n)/dt.
  subroutine test_prescribed_rotation()
    real(wp), parameter :: BETA = 1.3_wp, MZ = 0.7_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:), x2(:,:)
    integer, allocatable :: conn(:,:), conn2(:,:)
    real(wp) :: moment(3, 2), zero(3, 2), dt, t, worst(2), worst_reaction, rf(3), rm(3)
    real(wp) :: u_old(3), u(3), v(3), worst_secant
    integer :: n, b
    call make_box([1, 1, 1], [2.0_wp, 1.0_wp, 0.5_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    call make_box([1, 1, 1], [2.0_wp, 1.0_wp, 0.5_wp], [5.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, &
                  x2, conn2)
    call make_model(model, 3, reshape([x, x2], [3, 16]), reshape([conn, conn2 + 8], [8, 2]), &
                    TOPO_HEX8, ELEM_SOLID, [1, 2], 2)
    call add_motion(model, 1, 7, 0, add_curve(model, [0.0_wp], [BETA]))
    call add_motion(model, 2, 7, 2, add_curve(model, [0.0_wp, 1.0_wp], [0.0_wp, BETA]))
    call rigid_bodies_build(model, zeros(16), bodies, status)
    call check(status%ok, 'prescribed rotation: built')
    moment = 0.0_wp
    moment(3, 1) = MZ
    zero = 0.0_wp
    dt = 2.0e-3_wp
    t = 0.0_wp
    worst = 0.0_wp
    worst_reaction = 0.0_wp
    worst_secant = 0.0_wp
    call rigid_body_point_motion(bodies, 1, x(:, 7), u_old, v)
    do n = 1, 400
      call advance_step(model, bodies, n, t, dt, zero, moment)
      t = t + dt
      do b = 1, 2
        worst(b) = max(worst(b), maxval(abs(bodies%body(b)%rotation - &
                       axis_angle([0.0_wp, 0.0_wp, 1.0_wp], BETA*t))))
      end do
      call rigid_body_reaction(bodies, 1, rf, rm)
      if (n > 1) worst_reaction = max(worst_reaction, maxval(abs(rm - [0.0_wp, 0.0_wp, -MZ])))
      call rigid_body_point_motion(bodies, 1, x(:, 7), u, v)
      worst_secant = max(worst_secant, maxval(abs(v - (u - u_old)/dt)))
      u_old = u
    end do
    ! measured: 6.7e-16 and 5.6e-16 (rotations), 3.5e-13 (reaction), 1.1e-13 (secant)
    call check(worst(1) < 1.0e-12_wp, 'prescribed rotation: omega (VAD 0) gives Rz(beta t)', &
               real_text(worst(1)))
    call check(worst(2) < 1.0e-12_wp, 'prescribed rotation: angle (VAD 2) gives Rz(beta t)', &
               real_text(worst(2)))
    call check(worst_reaction < 1.0e-12_wp, 'prescribed rotation: reaction moment -M_z', &
               real_text(worst_reaction))
    call check(worst_secant < 1.0e-10_wp, 'prescribed rotation: node velocity = (u - u_old)/dt', &
               real_text(worst_secant))
    call check_close(u(1:2), matmul(axis_2d(BETA*t), x(1:2, 7) - [1.0_wp, 0.5_wp]) + &
                     [1.0_wp, 0.5_wp] - x(1:2, 7), 1.0e-12_wp, &
                     'prescribed rotation: node displacement', atol=1.0e-13_wp)
  end subroutine test_prescribed_rotation

  !> CMO = 1, CON1 = 4 (x, y held), CON2 = 7 (rotations held) under a force and moment:
  !> only z moves, as F_z t^2/(2m); reactions -F_x, -F_y and -M.
  subroutine test_constraints()
    real(wp), parameter :: FORCE(3) = [1.0_wp, 2.0_wp, 3.0_wp]
    real(wp), parameter :: MOMENT(3) = [0.5_wp, -0.2_wp, 0.1_wp]
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: f(3, 1), mom(3, 1), dt, t, m, rf(3), rm(3)
    integer :: n
    call make_box([1, 1, 1], [1.0_wp, 2.0_wp, 1.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    call make_model(model, 3, x, conn, TOPO_HEX8, ELEM_SOLID, [1], 1)
    model%materials(1)%cmo = 1
    model%materials(1)%con1 = 4
    model%materials(1)%con2 = 7
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(status%ok, 'constraints: built')
    m = bodies%body(1)%mass
    f(:, 1) = FORCE
    mom(:, 1) = MOMENT
    dt = 1.0e-2_wp
    t = 0.0_wp
    do n = 1, 100
      call advance_step(model, bodies, n, t, dt, f, mom)
      t = t + dt
    end do
    associate (body => bodies%body(1))
      call check(all(body%centre(1:2) == body%centre0(1:2)), 'constraints: CON1 = 4 holds x, y')
      call check_close(body%centre(3) - body%centre0(3), FORCE(3)*t**2/(2.0_wp*m), 1.0e-12_wp, &
                       'constraints: z free under F_z')
      call check(all(body%rotation == identity3()) .and. all(body%omega == 0.0_wp), &
                 'constraints: CON2 = 7 holds the rotations')
    end associate
    call rigid_body_reaction(bodies, 1, rf, rm)
    call check_close(rf, [-FORCE(1), -FORCE(2), 0.0_wp], 1.0e-15_wp, 'constraints: reaction force')
    call check_close(rm, -MOMENT, 1.0e-15_wp, 'constraints: reaction moment')
  end subroutine test_constraints

  !> CON2 = 4 (rotations about x and y held) on a box tilted about y (so I_xz /= 0) under a
  !> moment M_z: omega = (0, 0, M_z t/I_zz) at every half step (I_zz does not change by
  !> rotations about z), no reaction about z.
  subroutine test_partial_rotation_constraint()
    real(wp), parameter :: MZ = 0.4_wp, TILT = 0.5_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: mom(3, 1), zero(3, 1), dt, t, izz, worst, rf(3), rm(3), worst_rz
    integer :: n
    call make_box([1, 1, 1], [3.0_wp, 1.0_wp, 0.5_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    x = matmul(axis_angle([0.0_wp, 1.0_wp, 0.0_wp], TILT), x)
    call make_model(model, 3, x, conn, TOPO_HEX8, ELEM_SOLID, [1], 1)
    model%materials(1)%cmo = 1
    model%materials(1)%con2 = 4
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    izz = bodies%body(1)%inertia0(3, 3)
    call check(abs(bodies%body(1)%inertia0(1, 3)) > 0.1_wp*izz, &
               'partial rotation constraint: the tilted box has I_xz')
    mom = 0.0_wp
    mom(3, 1) = MZ
    zero = 0.0_wp
    dt = 1.0e-2_wp
    t = 0.0_wp
    worst = 0.0_wp
    worst_rz = 0.0_wp
    do n = 1, 200
      call advance_step(model, bodies, n, t, dt, zero, mom)
      worst = max(worst, maxval(abs(bodies%body(1)%omega - &
                                    [0.0_wp, 0.0_wp, MZ*(t + 0.5_wp*dt)/izz])))
      call rigid_body_reaction(bodies, 1, rf, rm)
      worst_rz = max(worst_rz, abs(rm(3)))
      t = t + dt
    end do
    ! measured: 3.3e-16 and 0
    call check(worst < 1.0e-13_wp, 'partial rotation constraint: omega = (0, 0, M t/I_zz)', &
               real_text(worst))
    call check(worst_rz < 1.0e-13_wp, 'partial rotation constraint: no reaction about z', &
               real_text(worst_rz))
  end subroutine test_partial_rotation_constraint

  !> 2D (plane strain) body, rectangle a x b of triangles with unit thickness: m = rho a b,
  !> I_zz = m (a^2 + b^2)/12; a couple M turns it by theta = M t^2/(2 I_zz) (exact in the
  !> central difference with dt_avg = dt/2 first), nodes follow Rz(theta); z and the
  !> rotations about x, y stay zero.
  subroutine test_2d_body()
    real(wp), parameter :: A = 2.0_wp, B = 1.0_wp, RHO = 3.0_wp, F = 0.5_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: force_sum(3, 1), moment_sum(3, 1), dt, t, m, izz, u(2), v(2), theta
    real(wp) :: p1(2), p2(2), worst_omega, c(2), omega_expected
    integer :: n
    call make_rectangle(4, 2, A, B, TOPO_TRI3, x, conn)
    call make_model(model, 2, x, conn, TOPO_TRI3, ELEM_SHELL, ones(size(conn, 2)), 1)
    model%materials(1)%density = RHO
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(status%ok, '2D body: built')
    m = RHO*A*B
    izz = m*(A**2 + B**2)/12.0_wp
    call check_close(bodies%body(1)%mass, m, 1.0e-14_wp, '2D body: mass (unit thickness)')
    call check_close(bodies%body(1)%inertia0(3, 3), izz, 1.0e-14_wp, '2D body: I_zz')
    c = [A/2, B/2]
    dt = 1.0e-2_wp
    t = 0.0_wp
    worst_omega = 0.0_wp
    omega_expected = 0.0_wp
    do n = 1, 150
      ! a couple: +F y at the right middle, -F y at the left middle (current positions)
      force_sum = 0.0_wp
      moment_sum = 0.0_wp
      theta = bodies%body(1)%angle(3)
      p1 = c + matmul(axis_2d(theta), [A/2, 0.0_wp])
      p2 = c + matmul(axis_2d(theta), [-A/2, 0.0_wp])
      call rigid_bodies_accumulate(bodies, 1, p1, [0.0_wp, F], force_sum, moment_sum)
      call rigid_bodies_accumulate(bodies, 1, p2, [0.0_wp, -F], force_sum, moment_sum)
      call advance_step(model, bodies, n, t, dt, force_sum, moment_sum)
      ! the couple about z is F A cos(theta) at t^n
      omega_expected = omega_expected + merge(0.5_wp*dt, dt, n == 1)*F*A*cos(theta)/izz
      worst_omega = max(worst_omega, abs(bodies%body(1)%omega(3) - omega_expected))
      t = t + dt
    end do
    call rigid_body_point_motion(bodies, 1, x(1:2, 1), u, v)
    theta = bodies%body(1)%angle(3)
    call check_close(u, matmul(axis_2d(theta), x(1:2, 1) - c) + c - x(1:2, 1), 1.0e-12_wp, &
                     '2D body: corner follows Rz(theta)', atol=1.0e-14_wp)
    call check(size(u) == 2, '2D body: 2-component point motion')
    call check(all(bodies%body(1)%omega(1:2) == 0.0_wp) .and. bodies%body(1)%velocity(3) == &
               0.0_wp, '2D body: no out-of-plane motion')
    call check_close(bodies%body(1)%centre, [c(1), c(2), 0.0_wp], 1.0e-14_wp, &
                     '2D body: a couple does not move the centre', atol=1.0e-15_wp)
    ! measured: 3.9e-16
    call check(worst_omega < 1.0e-13_wp, '2D body: omega from the couple of nodal forces', &
               real_text(worst_omega))
    call test_2d_constant_couple()
  end subroutine test_2d_body

  !> 2D rectangle under a constant moment M_z: theta = M t^2/(2 I_zz) exactly.
  subroutine test_2d_constant_couple()
    real(wp), parameter :: A = 2.0_wp, B = 1.0_wp, MZ = 0.3_wp
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    real(wp) :: mom(3, 1), zero(3, 1), dt, t, izz, u(2), v(2), theta
    integer :: n
    call make_rectangle(2, 2, A, B, TOPO_QUAD4, x, conn)
    call make_model(model, 2, x, conn, TOPO_QUAD4, ELEM_SHELL, ones(size(conn, 2)), 1)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    izz = bodies%body(1)%inertia0(3, 3)
    call check_close(izz, A*B*(A**2 + B**2)/12.0_wp, 1.0e-14_wp, '2D body: I_zz of quads')
    mom = 0.0_wp
    mom(3, 1) = MZ
    zero = 0.0_wp
    dt = 1.0e-2_wp
    t = 0.0_wp
    do n = 1, 200
      call advance_step(model, bodies, n, t, dt, zero, mom)
      t = t + dt
    end do
    theta = MZ*t**2/(2.0_wp*izz)
    call rigid_body_point_motion(bodies, 1, x(1:2, 1), u, v)
    ! measured: 2.2e-16 relative
    call check_close(u, matmul(axis_2d(theta), x(1:2, 1) - [A/2, B/2]) + [A/2, B/2] - x(1:2, 1), &
                     1.0e-12_wp, '2D body: theta = M t^2/(2 I_zz) under a constant moment', &
                     atol=1.0e-14_wp)
  end subroutine test_2d_constant_couple

  ! ------------------------------------------------------------------ errors

  !> Shells of zero thickness: no mass, an error unless every dof is held; a node of two
  !> rigid parts; DOF 5 in 2D; rigid solids in 2D.
  subroutine test_build_errors()
    type(model_t) :: model
    type(rigid_bodies_t) :: bodies
    type(status_t) :: status
    real(wp), allocatable :: x(:,:)
    integer, allocatable :: conn(:,:)
    call make_rectangle(2, 1, 1.0_wp, 1.0_wp, TOPO_QUAD4, x, conn)
    call make_model(model, 3, x, conn, TOPO_QUAD4, ELEM_SHELL, [1, 1], 1)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(.not. status%ok, 'errors: massless shells with free dofs fail', status%message)
    model%materials(1)%cmo = 1
    model%materials(1)%con1 = 7
    model%materials(1)%con2 = 7
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(status%ok, 'errors: massless shells with every dof held are fine')
    model%materials(1)%con2 = 3
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(.not. status%ok, 'errors: free rotation without inertia fails')
    call add_motion(model, 1, 5, 0, 0)
    call add_motion(model, 1, 6, 0, 0)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(status%ok, 'errors: ... unless those rotations are prescribed')

    call make_model(model, 3, x, conn, TOPO_QUAD4, ELEM_SHELL, [1, 2], 2)
    model%sections%thickness(1) = 0.1_wp
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(.not. status%ok, 'errors: a node of two rigid parts fails', status%message)

    call make_model(model, 2, x, conn, TOPO_QUAD4, ELEM_SHELL, [1, 1], 1)
    call add_motion(model, 1, 5, 0, 0)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(.not. status%ok, 'errors: DOF 5 in 2D fails', status%message)

    call make_box([1, 1, 1], [1.0_wp, 1.0_wp, 1.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], TOPO_HEX8, x, conn)
    call make_model(model, 2, x, conn, TOPO_HEX8, ELEM_SOLID, [1], 1)
    call rigid_bodies_build(model, zeros(size(x, 2)), bodies, status)
    call check(.not. status%ok, 'errors: rigid solids in 2D fail', status%message)
  end subroutine test_build_errors

  ! ------------------------------------------------------------------ small helpers

  !> Rotation by angle about the unit axis n, written out (cos, sin and n n^T).
  pure function axis_angle(n, angle) result(r)
    real(wp), intent(in) :: n(3), angle          !< unit axis, angle
    real(wp) :: r(3, 3)
    real(wp) :: c, s
    integer :: i, j
    c = cos(angle)
    s = sin(angle)
    do j = 1, 3
      do i = 1, 3
        r(i, j) = (1.0_wp - c)*n(i)*n(j)
      end do
      r(j, j) = r(j, j) + c
    end do
    r(2, 1) = r(2, 1) + s*n(3)
    r(1, 2) = r(1, 2) - s*n(3)
    r(3, 1) = r(3, 1) - s*n(2)
    r(1, 3) = r(1, 3) + s*n(2)
    r(3, 2) = r(3, 2) + s*n(1)
    r(2, 3) = r(2, 3) - s*n(1)
  end function axis_angle

  !> 2 x 2 rotation by angle.
  pure function axis_2d(angle) result(r)
    real(wp), intent(in) :: angle                !< angle
    real(wp) :: r(2, 2)
    r = reshape([cos(angle), sin(angle), -sin(angle), cos(angle)], [2, 2])
  end function axis_2d

  !> R J R^T.
  pure function rotate(j, r) result(m)
    real(wp), intent(in) :: j(3, 3), r(3, 3)     !< tensor, rotation
    real(wp) :: m(3, 3)
    m = matmul(r, matmul(j, transpose(r)))
  end function rotate

  !> Inertia about a point at offset d from the centre of a body of mass m and central
  !> inertia j: j + m (|d|^2 1 - d d^T).
  pure function shifted(j, m, d) result(s)
    real(wp), intent(in) :: j(3, 3), m, d(3)     !< central inertia, mass, offset
    real(wp) :: s(3, 3)
    integer :: a, b
    do b = 1, 3
      do a = 1, 3
        s(a, b) = j(a, b) - m*d(a)*d(b)
      end do
      s(b, b) = s(b, b) + m*dot_product(d, d)
    end do
  end function shifted

  !> Step n from t to t + dt (dt_avg = dt/2 in the first step); t itself is not changed.
  subroutine advance_step(model, bodies, n, t, dt, force, moment)
    type(model_t), intent(in) :: model           !< the model
    type(rigid_bodies_t), intent(inout) :: bodies    !< the bodies
    integer, intent(in) :: n                     !< step number, from 1
    real(wp), intent(in) :: t, dt                !< t^n, step
    real(wp), intent(in) :: force(:,:), moment(:,:)  !< (3, nbody) at t^n
    call rigid_bodies_advance(model, bodies, t + 0.5_wp*dt, t + dt, &
                              merge(0.5_wp*dt, dt, n == 1), dt, force, moment)
  end subroutine advance_step

  !> n ones (part numbers of a one-part mesh).
  pure function ones(n) result(a)
    integer, intent(in) :: n                     !< length
    integer :: a(n)
    a = 1
  end function ones

  !> n zero masses.
  pure function zeros(n) result(a)
    integer, intent(in) :: n                     !< length
    real(wp) :: a(n)
    a = 0.0_wp
  end function zeros

  pure function identity3() result(m)
    real(wp) :: m(3, 3)
    m = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  end function identity3

  pure function diagonal(m) result(d)
    real(wp), intent(in) :: m(3, 3)
    real(wp) :: d(3)
    d = [m(1, 1), m(2, 2), m(3, 3)]
  end function diagonal

  pure function off_diagonal(m) result(d)
    real(wp), intent(in) :: m(3, 3)
    real(wp) :: d(3)
    d = [m(1, 2), m(1, 3), m(2, 3)]
  end function off_diagonal

  pure function cross3(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)
    real(wp) :: c(3)
    c(1) = a(2)*b(3) - a(3)*b(2)
    c(2) = a(3)*b(1) - a(1)*b(3)
    c(3) = a(1)*b(2) - a(2)*b(1)
  end function cross3

  function real_text(x) result(s)
    real(wp), intent(in) :: x
    character(len=24) :: s
    write(s, '(es12.4)') x
  end function real_text

end program test_rigid_bodies
