!> Tied contacts in the explicit analysis (doc/theory.md 10.12): every tied node s moves with
!> its master nodes, u_s = sum_c w_sc u_c (mefem_tied_contact), enforced kinematically in the
!> accelerations. After the nodal balance (a = F/m at every node):
!>  1. each tied node's net force F_s and mass m_s are gathered on every rank (one sum);
!>  2. every master node c takes them, a_c = (F_c + sum_s w_sc F_s)/(m_c + sum_s w_sc m_s) at
!>     its free dofs (the slave's force and mass moved onto the master nodes by the weights of
!>     the constraint: the virtual work of the constraint, and momentum, are kept exactly,
!>     sum_c w_sc = 1);
!>  3. the master accelerations are gathered on every rank (one sum) and each tied node takes
!>     a_s = sum_c w_sc a_c, so that v_s and u_s stay the combination of the masters'.
!> The sums run in a fixed order (tied nodes ascending, each master's entries ascending): the
!> same bits on any number of ranks. A tied node's SPCs are overridden (its master nodes' own
!> apply); prescribed motions on tied nodes and on their master nodes, and rigid-body nodes in
!> a tie, are errors when the analysis starts.
!>
!> Tiebreak (doc/theory.md 10.12): after step 3, every rank evaluates every held node of a
!> tie that can fail, with the same replicated data (the same decision everywhere): the tie's
!> force on the node, R_s = m_s a_s - F_s, split along the node's contact normal n (the
!> companion contact's n_A, pointing from the SURFA body to SURFB) into the tensile part
!> f_n = <R_s . n> (the tie pulling the node back onto SURFB) and the shear part
!> f_s = |R_s - (R_s . n) n|; stresses divide them by the node's SURFA area. The node is
!> released when (f_n/NFL)^NEN + (f_s/SFL)^MES >= 1 (stresses: exponents 2); from the next
!> step on it moves by its own forces, its SPCs apply again, and the companion contact acts
!> at it (mefem_mortar_contact's held mask).
module mefem_explicit_ties
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t, fatal, warn, say
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t, ON_NODE, ON_NODE_SET, TIEBREAK_NONE, TIEBREAK_STRESS
  use mefem_tied_contact, only: tied_contact_build
  use mefem_explicit_state, only: explicit_state_t
  use mefem_explicit_layout, only: explicit_layout_t, explicit_layout_local_node
  use mefem_boundary_conditions, only: target_nodes
  use mefem_comm, only: comm_sum
  implicit none
  private

  public :: explicit_ties_set_up, tie_accelerations

contains

  !> Build the ties (replicated), check them against the rigid bodies and prescribed motions,
  !> report them, and set this rank's view: local slots, SPCs of tied nodes cleared, their
  !> initial velocities the interpolation of their masters' (v_global: the deck's, SPCs
  !> applied). Collective only in the sense that every rank does the same.
  subroutine explicit_ties_set_up(model, layout, v_global, s)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    real(wp), intent(in) :: v_global(:,:)             !< (dim, mesh nodes) initial velocities
    type(explicit_state_t), intent(inout) :: s        !< local state (rigid bodies set up)
    type(status_t) :: status
    logical, allocatable :: tied_mesh(:), master_mesh(:)
    integer, allocatable :: nodes(:)
    integer :: k, i, j, l, g
    call tied_contact_build(model, s%tied, status)
    if (.not. status%ok) call fatal('explicit: '//status%message)
    associate (t => s%tied)
      allocate(tied_mesh(model%nodes%n), master_mesh(model%nodes%n))
      tied_mesh = .false.
      master_mesh = .false.
      tied_mesh(t%slave) = .true.
      master_mesh(t%master_node) = .true.
      ! rigid-body nodes (a segment or node set may hold some)
      do g = 1, model%nodes%n
        if (.not. (tied_mesh(g) .or. master_mesh(g))) cycle
        if (s%bodies%node_body(g) > 0) call fatal('explicit: node '// &
            itoa(model%nodes%id(g))//' of a tied contact belongs to a rigid body: a tied '// &
            'contact joins deformable bodies (tie nodes to a rigid part with '// &
            '*CONSTRAINED_EXTRA_NODES)')
      end do
      ! prescribed motions on tied nodes or their masters
      do k = 1, model%n_motions
        if (model%motions(k)%target_kind /= ON_NODE .and. &
            model%motions(k)%target_kind /= ON_NODE_SET) cycle
        call target_nodes(model, model%motions(k)%target_kind, model%motions(k)%target, nodes)
        do i = 1, size(nodes)
          if (tied_mesh(nodes(i)) .or. master_mesh(nodes(i))) call fatal('explicit: node '// &
              itoa(model%nodes%id(nodes(i)))//' of a tied contact has a prescribed motion '// &
              '(*BOUNDARY_PRESCRIBED_MOTION at line '//itoa(model%motions(k)%src%line)// &
              '): a tied node moves with its master facet; drive the bodies elsewhere')
        end do
      end do
      do k = 1, model%n_ties
        j = count(t%tie == k)
        if (j == 0) then
          call warn(tie_name(model, k)//': no SURFA node lies on a SURFB facet within '// &
              'the tolerance: nothing is tied')
        else
          if (t%tolerance(k) > 0.0_wp) then
            call say('explicit: '//tie_name(model, k)//' ties '//itoa(j)//' nodes ('// &
                itoa(count(t%tie == k .and. t%dual))//' by dual mortar weights; tolerance '// &
                rtoa(t%tolerance(k))//')')
          else
            call say('explicit: '//tie_name(model, k)//' ties '//itoa(j)//' nodes ('// &
                itoa(count(t%tie == k .and. t%dual))//' by dual mortar weights)')
          end if
        end if
        if (t%untied(k) > 0 .and. j > 0) call warn(tie_name(model, k)//': '// &
            itoa(t%untied(k))//' SURFA nodes are not tied (no SURFB facet within the '// &
            'tolerance; the first is node '//itoa(model%nodes%id(t%first_untied(k)))//')')
      end do
      ! this rank's view
      allocate(s%tie_slave_local(t%n), s%tie_master_local(t%nmaster), s%tie_buffer(4, t%n), &
               s%tie_master_buffer(3, t%nmaster), s%tied_node(s%nnode), s%tie_fixed(3, t%n))
      s%tied_node = .false.
      s%tie_fixed = .false.
      do i = 1, t%n
        l = explicit_layout_local_node(layout, t%slave(i))
        s%tie_slave_local(i) = l
        if (l == 0) cycle
        s%tied_node(l) = .true.
        s%tie_fixed(1:s%dim, i) = s%fixed(:, l)
        s%fixed(:, l) = .false.
        s%v(:, l) = 0.0_wp
        do j = t%start(i), t%start(i + 1) - 1
          s%v(:, l) = s%v(:, l) + t%weight(j)*v_global(:, t%master(j))
        end do
      end do
      do j = 1, t%nmaster
        s%tie_master_local(j) = explicit_layout_local_node(layout, t%master_node(j))
      end do
      if (t%tiebreak) call tiebreak_set_up(model, s)
    end associate
  end subroutine explicit_ties_set_up

  !> The tiebreaks' view: a stress criterion needs each node's area; the companion contacts
  !> leave the held nodes to their ties (held masks).
  subroutine tiebreak_set_up(model, s)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state (contact set up)
    integer :: i, k, c, a
    associate (t => s%tied)
      do i = 1, t%n
        k = t%tie(i)
        if (t%fail_kind(k) == TIEBREAK_STRESS .and. .not. t%area(i) > 0.0_wp) call fatal( &
            'explicit: '//tie_name(model, k)//': node '//itoa(t%slave_id(i))//' lies on no '// &
            'SURFA facet, so it has no area for the failure stresses NFLS/SFLS (give SURFA '// &
            'as segments or parts, or use *CONTACT_TIEBREAK_NODES_TO_SURFACE with forces)')
      end do
      do k = 1, model%n_ties
        c = t%companion(k)
        if (c == 0) cycle
        associate (it => s%contact%interfaces(c))
          allocate(it%held(size(it%slave%nodes)))
          it%held = .false.
          do i = 1, t%n
            if (t%tie(i) /= k) cycle
            a = it%slave_index(t%slave(i))
            if (a > 0) it%held(a) = .true.
          end do
        end associate
        call say('explicit: '//tie_name(model, k)//' is a tiebreak: '// &
            itoa(count(t%tie == k))//' tied nodes until their '// &
            trim(merge('stresses', 'forces  ', t%fail_kind(k) == TIEBREAK_STRESS))// &
            ' fail them (normal '//rtoa(t%fail_limits(1, k))//', shear '// &
            rtoa(t%fail_limits(2, k))//'), then contact')
      end do
    end associate
  end subroutine tiebreak_set_up

  !> Steps 1-3 of the module's description, after the nodal balance (s%a = F/m, the forces
  !> of this step in s%f_int, s%f_ext, s%f_con). Collective.
  subroutine tie_accelerations(s, with_contact, time)
    type(explicit_state_t), intent(inout) :: s        !< local state
    logical, intent(in) :: with_contact               !< s%f_con may be nonzero
    real(wp), intent(in) :: time                      !< time of this state (messages)
    real(wp) :: force(3), mass
    integer :: i, j, e, l, d, dim
    dim = s%dim
    ! 1. the tied nodes' net forces and masses (from their owners)
    s%tie_buffer = 0.0_wp
    do i = 1, s%tied%n
      if (.not. s%tied%held(i)) cycle
      l = s%tie_slave_local(i)
      if (l == 0) cycle
      if (.not. s%owned(l)) cycle
      s%tie_buffer(1:dim, i) = net_force(l)
      s%tie_buffer(4, i) = s%mass(l)
    end do
    call comm_sum(s%tie_buffer)
    ! 2. the master nodes' accelerations, with the tied nodes' forces and masses
    s%tie_master_buffer = 0.0_wp
    do j = 1, s%tied%nmaster
      l = s%tie_master_local(j)
      if (l == 0) cycle
      force = 0.0_wp
      force(1:dim) = net_force(l)
      mass = s%mass(l)
      do e = s%tied%entry_start(j), s%tied%entry_start(j + 1) - 1
        i = s%tied%entry_slave(e)
        if (.not. s%tied%held(i)) cycle
        force = force + s%tied%entry_weight(e)*s%tie_buffer(1:3, i)
        mass = mass + s%tied%entry_weight(e)*s%tie_buffer(4, i)
      end do
      do d = 1, dim
        if (s%active(l) .and. .not. (s%fixed(d, l) .or. s%driven(d, l))) then
          s%a(d, l) = force(d)/mass
        else
          s%a(d, l) = 0.0_wp
        end if
      end do
      if (s%owned(l)) s%tie_master_buffer(1:dim, j) = s%a(:, l)
    end do
    ! 3. the tied nodes follow their master points
    call comm_sum(s%tie_master_buffer)
    do i = 1, s%tied%n
      if (.not. s%tied%held(i)) cycle
      l = s%tie_slave_local(i)
      if (l == 0) cycle
      s%a(:, l) = 0.0_wp
      do j = s%tied%start(i), s%tied%start(i + 1) - 1
        s%a(:, l) = s%a(:, l) + s%tied%weight(j)*s%tie_master_buffer(1:dim, s%tied%master_slot(j))
      end do
    end do
    if (s%tied%tiebreak) call tiebreak_failures(s, time)
  contains
    !> Net force f_ext + f_con - f_int at local node n (as the nodal balance sums it).
    function net_force(n) result(f)
      integer, intent(in) :: n                        !< local node
      real(wp) :: f(dim)
      f = 0.0_wp
      if (s%with_external) f = s%f_ext(:, n)
      if (with_contact) f = f + s%f_con(:, n)
      f = f - s%f_int(:, n)
    end function net_force
  end subroutine tie_accelerations

  !> The tiebreak criterion at every held node of a tie that can fail (module header), with
  !> the tie's force of this step; the nodes that fail are released from the next step on.
  !> Every rank decides alike (replicated data, the same order). Collective only in the
  !> sense that every rank does the same.
  subroutine tiebreak_failures(s, time)
    type(explicit_state_t), intent(inout) :: s        !< local state (step 3 done)
    real(wp), intent(in) :: time                      !< time of this state (messages)
    real(wp) :: accel(3), reaction(3), normal(3), f_normal, f_shear, measure
    integer :: i, j, k, l, a, c, dim, released, first
    dim = s%dim
    do k = 1, size(s%tied%fail_kind)
      if (s%tied%fail_kind(k) == TIEBREAK_NONE) cycle
      c = s%tied%companion(k)
      released = 0
      first = 0
      do i = 1, s%tied%n
        if (s%tied%tie(i) /= k .or. .not. s%tied%held(i)) cycle
        accel = 0.0_wp
        do j = s%tied%start(i), s%tied%start(i + 1) - 1
          accel(1:dim) = accel(1:dim) + s%tied%weight(j)* &
                         s%tie_master_buffer(1:dim, s%tied%master_slot(j))
        end do
        reaction = s%tie_buffer(4, i)*accel - s%tie_buffer(1:3, i)
        ! the node's contact normal (its SURFA side's, toward SURFB), where it has one
        normal = 0.0_wp
        a = 0
        if (c > 0) a = s%contact%interfaces(c)%slave_index(s%tied%slave(i))
        if (a > 0) then
          if (allocated(s%contact%interfaces(c)%normal)) then
            if (s%contact%interfaces(c)%area(a) > 0.0_wp) &
              normal = s%contact%interfaces(c)%normal(:, a)
          end if
        end if
        if (norm2(normal) > 0.0_wp) normal = normal/norm2(normal)
        f_normal = max(dot_product(reaction, normal), 0.0_wp)
        f_shear = norm2(reaction - dot_product(reaction, normal)*normal)
        if (s%tied%fail_kind(k) == TIEBREAK_STRESS) then
          f_normal = f_normal/s%tied%area(i)
          f_shear = f_shear/s%tied%area(i)
        end if
        measure = (f_normal/s%tied%fail_limits(1, k))**s%tied%fail_limits(3, k) + &
                  (f_shear/s%tied%fail_limits(2, k))**s%tied%fail_limits(4, k)
        if (measure < 1.0_wp) cycle
        ! released: its own forces, SPCs and the companion contact from now on
        s%tied%held(i) = .false.
        released = released + 1
        if (first == 0) first = s%tied%slave_id(i)
        l = s%tie_slave_local(i)
        if (l > 0) then
          s%tied_node(l) = .false.
          s%fixed(:, l) = s%tie_fixed(1:dim, i)
        end if
        if (a > 0) s%contact%interfaces(c)%held(a) = .false.
      end do
      if (released > 0) call say('explicit: t = '//rtoa(time)//': tiebreak '// &
          tiebreak_label(k)//': '//itoa(released)//' node(s) released (first: node '// &
          itoa(first)//'), '//itoa(count(s%tied%held .and. s%tied%tie == k))//' still tied')
    end do
  contains
    !> "contact ID" or "number k" (no model here: the companion contact's id).
    function tiebreak_label(k) result(text)
      integer, intent(in) :: k                        !< the tie
      character(len=:), allocatable :: text
      text = 'number '//itoa(k)
      if (s%tied%companion(k) > 0) then
        if (s%contact%interfaces(s%tied%companion(k))%id /= 0) &
          text = 'contact '//itoa(s%contact%interfaces(s%tied%companion(k))%id)
      end if
    end function tiebreak_label
  end subroutine tiebreak_failures

  !> "contact ID" or "tied contact number k (no id)".
  function tie_name(model, k) result(text)
    type(model_t), intent(in) :: model                !< the model
    integer, intent(in) :: k                          !< index in model%ties
    character(len=:), allocatable :: text
    if (model%ties(k)%id /= 0) then
      text = 'contact '//itoa(model%ties(k)%id)
    else
      text = 'tied contact number '//itoa(k)//' (no id)'
    end if
  end function tie_name

end module mefem_explicit_ties
