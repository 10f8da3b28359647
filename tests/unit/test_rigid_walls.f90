!> Planar rigid walls (mefem_rigid_walls): a node mass hitting a wall stops on the plane
!> with the impulse m v0 and the work -m v0^2/2; Coulomb friction FRIC = 0 (tangential
!> velocity kept), 0.3 (reduced by 0.3 times the normal change, or to zero), 1 (sticks);
!> oblique 3D and 2D walls; nodes in front untouched; BIRTH/DEATH; owned nodes only in the
!> force; the node selection of rigid_wall_nodes (NSID, NSIDEX, OFFSET, skip, enriched nodes).
! ranks: 1
program test_rigid_walls
  use mefem_kinds, only: wp
  use mefem_model, only: model_t, rigid_wall_t, set_t, SET_NODE
  use mefem_rigid_walls, only: rigid_wall_nodes, rigid_wall_constrain, rigid_wall_normal
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal
  implicit none

  real(wp), parameter :: MASS = 2.5_wp, V0 = 2.0_wp, DT = 0.01_wp, Z0 = 0.1037_wp
  integer, parameter :: STEPS = 30

  call test_start('rigid_walls')
  call test_impact(0.0_wp, 1.5_wp, 'FRIC 0')
  call test_impact(0.3_wp, 1.5_wp, 'FRIC 0.3')
  call test_impact(0.3_wp, 0.1_wp*V0, 'FRIC 0.3 slow')
  call test_impact(1.0_wp, 1.5_wp, 'FRIC 1')
  call test_oblique_3d()
  call test_2d_wall()
  call test_birth_death_and_ownership()
  call test_node_selection()
  call test_finish()

contains

  !> Wall z = 0 (normal +z); node 1 starts at z = Z0 with v = (vt0, 0, -V0), node 2 far in
  !> front. No forces: u^{n+1} = u^n + dt v, then the wall.
  subroutine test_impact(fric, vt0, name)
    real(wp), intent(in) :: fric, vt0            !< FRIC, initial tangential speed
    character(len=*), intent(in) :: name         !< label
    type(rigid_wall_t) :: wall
    real(wp) :: x0(3, 2), u(3, 2), u_old(3, 2), v(3, 2), m(2), force(3), impulse(3), work
    real(wp) :: total_work, vt_want, x_stick, time, v2_free(3), u2_free(3)
    integer :: n, contact_step, nodes(2)
    wall%tail = [0.0_wp, 0.0_wp, 0.0_wp]
    wall%head = [0.0_wp, 0.0_wp, 2.0_wp]
    wall%friction = fric
    x0(:, 1) = [0.3_wp, -0.2_wp, Z0]
    x0(:, 2) = [1.0_wp, 1.0_wp, 5.0_wp]
    u = 0.0_wp
    v(:, 1) = [vt0, 0.0_wp, -V0]
    v(:, 2) = [0.1_wp, 0.2_wp, -0.3_wp]
    v2_free = v(:, 2)
    u2_free = 0.0_wp
    m = MASS
    nodes = [1, 2]
    impulse = 0.0_wp
    total_work = 0.0_wp
    contact_step = 0
    time = 0.0_wp
    do n = 1, STEPS
      u_old = u
      u = u + DT*v
      u2_free = u2_free + DT*v2_free
      time = time + DT
      call rigid_wall_constrain(wall, 3, x0, u, v, u_old, m, DT, time, nodes, [.true., .true.], &
                                force, work)
      if (contact_step == 0 .and. any(force /= 0.0_wp)) contact_step = n
      impulse = impulse + force*DT
      total_work = total_work + work
    end do
    ! measured (all cases): position exactly 0, impulse and work within 2e-16 relative
    call check(abs(x0(3, 1) + u(3, 1)) < 1.0e-14_wp .and. v(3, 1) == 0.0_wp, &
               name//': the node stops on the plane')
    call check_close(impulse(3), -MASS*V0, 1.0e-12_wp, name//': normal impulse on the wall -m v0')
    if (fric == 0.0_wp) then
      call check(v(1, 1) == vt0 .and. v(2, 1) == 0.0_wp, name//': tangential velocity unchanged')
      call check_close(total_work, -0.5_wp*MASS*V0**2, 1.0e-12_wp, name//': work -m v0^2/2')
      call check(impulse(1) == 0.0_wp, name//': no tangential impulse')
    else if (fric < 1.0_wp) then
      vt_want = max(0.0_wp, vt0 - fric*V0)
      call check_close(v(1, 1), vt_want, 1.0e-12_wp, name//': tangential velocity reduced by '// &
                       'FRIC times the normal change (or to zero)', atol=1.0e-14_wp)
      call check_close(impulse(1), MASS*(vt0 - vt_want), 1.0e-12_wp, &
                       name//': tangential impulse on the wall')
      call check_close(total_work, 0.5_wp*MASS*(vt_want**2 - vt0**2 - V0**2), 1.0e-12_wp, &
                       name//': work = change of kinetic energy')
    else
      ! no sliding: x stays where the node was at the start of the contact step
      x_stick = x0(1, 1) + (contact_step - 1)*DT*vt0
      call check(v(1, 1) == 0.0_wp, name//': no tangential velocity in contact')
      call check_close(x0(1, 1) + u(1, 1), x_stick, 1.0e-14_wp, name//': the node sticks')
    end if
    call check(contact_step == ceiling(Z0/(V0*DT)), name//': contact in the step of crossing')
    call check(all(u(:, 2) == u2_free) .and. all(v(:, 2) == v2_free), &
               name//': node in front untouched')
  end subroutine test_impact

  !> Wall through (1, 1, 1) with normal along (1, 2, 3); a node approaching along -n with a
  !> tangential velocity: on the plane after contact, normal velocity zero, tangential kept.
  subroutine test_oblique_3d()
    type(rigid_wall_t) :: wall
    real(wp) :: x0(3, 1), u(3, 1), u_old(3, 1), v(3, 1), force(3), normal(3), tangent(3), time
    real(wp) :: gap
    integer :: n
    wall%tail = [1.0_wp, 1.0_wp, 1.0_wp]
    wall%head = [2.0_wp, 3.0_wp, 4.0_wp]
    normal = [1.0_wp, 2.0_wp, 3.0_wp]/sqrt(14.0_wp)
    call check_close(rigid_wall_normal(wall, 3), normal, 1.0e-15_wp, 'oblique: unit normal')
    tangent = [2.0_wp, -1.0_wp, 0.0_wp]/sqrt(5.0_wp)
    x0(:, 1) = wall%tail + 0.0731_wp*normal + 0.4_wp*tangent
    v(:, 1) = -V0*normal + 0.7_wp*tangent
    u = 0.0_wp
    time = 0.0_wp
    do n = 1, STEPS
      u_old = u
      u = u + DT*v
      time = time + DT
      call rigid_wall_constrain(wall, 3, x0, u, v, u_old, [MASS], DT, time, [1], [.true.], force)
    end do
    gap = dot_product(x0(:, 1) + u(:, 1) - wall%tail, normal)
    ! round-off: a few eps |x|, eps |v| (|x| ~ 2, |v| = 2.1); measured: gap 8.7e-16, normal
    ! velocity 3.3e-15, tangential 2.9e-15
    call check(abs(gap) < 1.0e-14_wp, 'oblique: node on the plane', real_text(gap))
    call check(abs(dot_product(v(:, 1), normal)) < 1.0e-14_wp, 'oblique: normal velocity zero', &
               real_text(dot_product(v(:, 1), normal)))
    call check_close(v(:, 1), 0.7_wp*tangent, 1.0e-13_wp, 'oblique: tangential velocity kept', &
                     atol=1.0e-14_wp)
  end subroutine test_oblique_3d

  !> 2D: wall through the origin with normal (1, 1)/sqrt(2), arrays (2, n); a node moving
  !> along -n: stops on the plane, impulse m v0 along -n.
  subroutine test_2d_wall()
    type(rigid_wall_t) :: wall
    real(wp) :: x0(2, 1), u(2, 1), u_old(2, 1), v(2, 1), force(3), impulse(3), normal(2), time
    integer :: n
    wall%tail = [0.0_wp, 0.0_wp, 7.0_wp]
    wall%head = [1.0_wp, 1.0_wp, 3.0_wp]        ! z is ignored in 2D
    normal = [1.0_wp, 1.0_wp]/sqrt(2.0_wp)
    x0(:, 1) = 0.05_wp*normal
    v(:, 1) = -V0*normal
    u = 0.0_wp
    impulse = 0.0_wp
    time = 0.0_wp
    do n = 1, STEPS
      u_old = u
      u = u + DT*v
      time = time + DT
      call rigid_wall_constrain(wall, 2, x0, u, v, u_old, [MASS], DT, time, [1], [.true.], force)
      impulse = impulse + force*DT
    end do
    call check(abs(dot_product(x0(:, 1) + u(:, 1), normal)) < 1.0e-14_wp, '2D: node on the plane')
    call check_close(impulse, [-MASS*V0*normal, 0.0_wp], 1.0e-12_wp, '2D: impulse -m v0 n', &
                     atol=1.0e-14_wp)
  end subroutine test_2d_wall

  !> Before BIRTH and after DEATH the wall does nothing; a node not owned is corrected but
  !> adds no force and no work.
  subroutine test_birth_death_and_ownership()
    type(rigid_wall_t) :: wall
    real(wp) :: x0(3, 1), u(3, 1), u_old(3, 1), v(3, 1), force(3), work, u_free(3, 1), v_free(3, 1)
    wall%tail = [0.0_wp, 0.0_wp, 0.0_wp]
    wall%head = [0.0_wp, 0.0_wp, 1.0_wp]
    wall%birth = 1.0_wp
    wall%death = 2.0_wp
    x0(:, 1) = [0.0_wp, 0.0_wp, 0.001_wp]
    u_old = 0.0_wp
    v(:, 1) = [0.0_wp, 0.0_wp, -1.0_wp]
    u = u_old + DT*v
    u_free = u
    v_free = v
    call rigid_wall_constrain(wall, 3, x0, u, v, u_old, [MASS], DT, 0.5_wp, [1], [.true.], force, &
                              work)
    call check(all(u == u_free) .and. all(v == v_free) .and. all(force == 0.0_wp), &
               'birth: inactive before BIRTH')
    call rigid_wall_constrain(wall, 3, x0, u, v, u_old, [MASS], DT, 2.5_wp, [1], [.true.], force, &
                              work)
    call check(all(u == u_free) .and. all(v == v_free), 'death: inactive after DEATH')
    call rigid_wall_constrain(wall, 3, x0, u, v, u_old, [MASS], DT, 1.5_wp, [1], [.false.], force, &
                              work)
    call check(abs(x0(3, 1) + u(3, 1)) < 1.0e-15_wp .and. all(force == 0.0_wp) .and. &
               work == 0.0_wp, &
               'ownership: a node not owned is corrected, adds no force or work')
  end subroutine test_birth_death_and_ownership

  !> rigid_wall_nodes on 6 mesh nodes, this rank holding global nodes 1 2 3 5 6 and two
  !> enriched nodes (7, 8).
  subroutine test_node_selection()
    type(model_t) :: model
    integer, allocatable :: nodes(:)
    integer, parameter :: NODE_GLOBAL(7) = [1, 2, 3, 5, 6, 7, 8]
    logical :: skip(6)
    integer :: i
    model%dimension = 3
    model%nodes%n = 6
    allocate(model%nodes%x(3, 6))
    do i = 1, 6
      model%nodes%x(:, i) = [0.0_wp, 0.0_wp, 0.1_wp*i]    ! heights 0.1 .. 0.6
    end do
    model%n_sets = 2
    allocate(model%sets(2))
    model%sets(1) = set_t(id=1, kind=SET_NODE, n=1, member_ids=[1], members=[1])
    model%sets(2) = set_t(id=2, kind=SET_NODE, n=2, member_ids=[2, 5], members=[2, 5])
    model%n_rigid_walls = 1
    allocate(model%rigid_walls(1))
    model%rigid_walls(1)%tail = [0.0_wp, 0.0_wp, 0.0_wp]
    model%rigid_walls(1)%head = [0.0_wp, 0.0_wp, 1.0_wp]
    ! NSID 0, NSIDEX {2, 5}: globals 1 3 6 -> local 1 3 5
    model%rigid_walls(1)%exempt_set = 2
    call rigid_wall_nodes(model, 1, NODE_GLOBAL, 6, nodes)
    call check(same(nodes, [1, 3, 5]), 'nodes: all mesh nodes minus NSIDEX, no enriched nodes')
    ! NSID {1} with OFFSET 0.35: globals 1 (set) and 2 3 (within 0.35), minus NSIDEX {2, 5}
    model%rigid_walls(1)%node_set = 1
    model%rigid_walls(1)%offset = 0.35_wp
    call rigid_wall_nodes(model, 1, NODE_GLOBAL, 6, nodes)
    call check(same(nodes, [1, 3]), 'nodes: NSID plus nodes within OFFSET, minus NSIDEX')
    model%rigid_walls(1)%exempt_set = 0
    skip = .false.
    skip(1) = .true.
    call rigid_wall_nodes(model, 1, NODE_GLOBAL, 6, nodes, skip)
    call check(same(nodes, [2, 3]), 'nodes: skipped nodes left out')
    ! a wall normal to z in 2D has no normal: no nodes
    model%dimension = 2
    call rigid_wall_nodes(model, 1, NODE_GLOBAL, 6, nodes)
    call check_equal(size(nodes), 0, 'nodes: none when the normal is out of the 2D plane')
  end subroutine test_node_selection

  !> A real for a message.
  function real_text(x) result(s)
    real(wp), intent(in) :: x                    !< value
    character(len=24) :: s
    write(s, '(es12.4)') x
  end function real_text

  !> Equal integer lists.
  logical function same(a, b)
    integer, intent(in) :: a(:), b(:)            !< lists
    same = size(a) == size(b)
    if (same) same = all(a == b)
  end function same

end program test_rigid_walls
