!> Linear constraints of the implicit and linear analyses, written as a change of unknowns
!> u = T u' of the Newton (or linear) system: the solver takes T^T K T and T^T R, the rows and
!> columns of the unknowns the constraints remove replaced by the identity and their residuals
!> by 0, and the increment goes back as du = T du'. Two kinds (doc/theory.md 6.7, 10.12):
!>  - SPCs in turned local systems (CID, skew conditions): at such a node the equations of its
!>    free global components are written in a node frame Q whose first columns are the fixed
!>    local directions (made orthonormal, stripped of their components along the node's fixed
!>    global dofs) and whose others complete it; the fixed components are removed (the
!>    condition holds exactly, as a global SPC's does). T is orthogonal there. A node with a
!>    driven (prescribed) dof is refused. The conditions of an SPC act while BT <= t <= DT
!>    (the step's end time);
!>  - tied contacts (*CONTACT_TIED_...): a tied node's component i is removed, u_s = sum_c
!>    w_sc u_c with the weights of mefem_tied_contact (the explicit analysis' ties); its
!>    residual goes to the master nodes with the same weights (the virtual work of the
!>    constraint). A tied node's own SPCs are overridden (its masters' apply); a tie at a skew
!>    node is refused.
!> The positions of T^T K T's entries depend on K's only, so the solver's analysis is kept.
module mefem_implicit_constraints
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: fatal
  use mefem_strings, only: itoa
  use mefem_model, only: model_t, ON_NODE, ON_NODE_SET
  use mefem_curves, only: curve_value
  use mefem_boundary_conditions, only: target_nodes
  use mefem_sparse_assembly, only: coo_matrix_t, coo_init, coo_add_rectangle, STORAGE_LOWER
  use mefem_comm, only: comm_rank
  use mefem_tied_contact, only: tied_nodes_t
  implicit none
  private

  public :: node_constraints_t, constraints_set_up, constraints_activate
  public :: constraints_residual, constraints_matrix, constraints_increment
  public :: constraints_prescribe, constraints_reaction

  !> length below which a direction is held by the node's earlier ones already
  real(wp), parameter :: DEPENDENT = 1.0e-8_wp
  !> a motion's component along a fixed dof, and the cosine of a motion's direction and an
  !> SPC's at one node, above which they are not normal
  real(wp), parameter :: ALIGNED = 1.0e-9_wp
  !> most unknowns an equation spreads over (a tied node's masters: the vertices of the SURFB
  !> facets its SURFA facets overlap)
  integer, parameter :: MAX_TARGETS = 64

  !> The constrained unknowns: the skew nodes with their frames, and the tied components.
  type :: node_constraints_t
    logical :: active = .false.                    !< some constraint (T is not I)
    integer :: n = 0                               !< skew nodes
    integer :: dim = 3
    integer, allocatable :: node(:)                !< (n) mesh node
    integer, allocatable :: n_free(:)              !< (n) its free global components
    integer, allocatable :: free(:,:)              !< (dim, n) which (1 x, 2 y, 3 z)
    integer, allocatable :: eq(:,:)                !< (dim, n) their equations
    integer, allocatable :: start(:)               !< (n + 1) its conditions in spc, dir
    integer, allocatable :: spc(:)                 !< the SPC of each condition (0: a motion)
    integer, allocatable :: motion(:)              !< the node motion (DOF 4/-4), or 0
    real(wp), allocatable :: dir(:,:)              !< (3, conditions) its direction
    real(wp), allocatable :: frame(:,:,:)          !< (dim, dim, n) Q on the free components
                                                   !< (n_free x n_free), fixed directions first
    integer, allocatable :: n_fixed(:)             !< (n) fixed components (active now)
    real(wp), allocatable :: drive(:)              !< (n) a motion's displacement along the
                                                   !< frame's first axis now, or huge: none
    integer, allocatable :: slot(:)                !< (equations) skew node of an equation, or 0
    integer, allocatable :: component(:)           !< (equations) its component there
    ! tied components: equation tie_eq(k) = sum of tie_weight(j) x equation tie_target(j),
    ! j = tie_start(k) .. tie_start(k + 1) - 1
    integer :: n_tied = 0                          !< tied components
    integer, allocatable :: tie_eq(:), tie_start(:), tie_target(:)
    real(wp), allocatable :: tie_weight(:)
    integer, allocatable :: tie_slot(:)            !< (equations) k of a tied component, or 0
  end type node_constraints_t

contains

  !> The constraints: the nodes of the SPCs with skew directions (spc%n_skew > 0), their
  !> conditions in deck order, their free components and equations (a node with a driven
  !> dof is an error); the tied components of tied (their equations, the masters' equations
  !> and weights; a tie at a skew node is an error).
  subroutine constraints_set_up(model, equation, n_equations, driven, tied, skew)
    type(model_t), intent(in) :: model                 !< resolved model
    integer, intent(in) :: equation(:,:)               !< (dim, nodes) equation numbers
    integer, intent(in) :: n_equations                 !< number of equations
    logical, intent(in) :: driven(:,:)                 !< (dim, mesh nodes) prescribed dofs
    type(tied_nodes_t), intent(in) :: tied             !< the ties (n = 0: none)
    type(node_constraints_t), intent(out) :: skew      !< the constraints
    integer, allocatable :: nodes(:), count_at(:), slot_of(:), next(:)
    integer :: k, i, j, g, m, pass, total
    skew%dim = size(equation, 1)
    allocate(count_at(size(driven, 2)))
    count_at = 0
    do pass = 1, 2
      total = 0
      do k = 1, model%n_spcs
        associate (spc => model%spcs(k))
          if (spc%n_skew == 0 .or. spc%target <= 0) cycle
          call target_nodes(model, spc%target_kind, spc%target, nodes)
          do i = 1, size(nodes)
            g = nodes(i)
            do j = 1, spc%n_skew
              total = total + 1
              if (pass == 1) then
                count_at(g) = count_at(g) + 1
              else
                m = next(slot_of(g))
                skew%spc(m) = k
                skew%motion(m) = 0
                skew%dir(:, m) = spc%skew(:, j)
                next(slot_of(g)) = m + 1
              end if
            end do
            if (pass == 1 .and. any(driven(:, g))) &
              call fatal('implicit: node '//itoa(model%nodes%id(g))//' has an SPC in a '// &
                  'turned system (CID '//itoa(spc%cid)//', *BOUNDARY_SPC at line '// &
                  itoa(spc%src%line)//') and a prescribed motion: the implicit analysis '// &
                  'does not take both at a node')
          end do
        end associate
      end do
      do k = 1, model%n_motions                       ! node motions along a vector
        associate (pm => model%motions(k))
          if (abs(pm%dof) /= 4 .or. (pm%target_kind /= ON_NODE .and. &
                                     pm%target_kind /= ON_NODE_SET)) cycle
          call target_nodes(model, pm%target_kind, pm%target, nodes)
          do i = 1, size(nodes)
            g = nodes(i)
            total = total + 1
            if (pass == 1) then
              count_at(g) = count_at(g) + 1
              if (any(driven(:, g))) call fatal('implicit: node '//itoa(model%nodes%id(g))// &
                  ' has a motion along a vector (DOF 4, line '//itoa(pm%src%line)//') and one '// &
                  'along an axis: the implicit analysis does not take both at a node')
              if (any(equation(:, g) == 0 .and. abs(pm%direction(1:skew%dim)) > ALIGNED)) &
                call fatal('implicit: node '//itoa(model%nodes%id(g))//' has a motion along '// &
                    'a vector (DOF 4, line '//itoa(pm%src%line)//') with a component along '// &
                    'a fixed dof')
            else
              m = next(slot_of(g))
              skew%spc(m) = 0
              skew%motion(m) = k
              skew%dir(:, m) = pm%direction
              next(slot_of(g)) = m + 1
            end if
          end do
        end associate
      end do
      if (pass == 1) then
        skew%n = count(count_at > 0)
        skew%node = pack([(g, g = 1, size(count_at))], count_at > 0)
        allocate(slot_of(size(count_at)), skew%start(skew%n + 1), skew%spc(total), &
                 skew%motion(total), skew%dir(3, total), skew%eq(skew%dim, skew%n), &
                 skew%free(skew%dim, skew%n), skew%n_free(skew%n), &
                 skew%frame(skew%dim, skew%dim, skew%n), skew%n_fixed(skew%n), &
                 skew%drive(skew%n))
        slot_of = 0
        skew%start(1) = 1
        skew%eq = 0
        skew%free = 0
        skew%n_fixed = 0                                ! (until constraints_activate)
        skew%drive = huge(1.0_wp)
        skew%frame = 0.0_wp
        do m = 1, skew%n
          g = skew%node(m)
          slot_of(g) = m
          skew%start(m + 1) = skew%start(m) + count_at(g)
          skew%n_free(m) = count(equation(:, g) > 0)
          skew%free(1:skew%n_free(m), m) = pack([(i, i = 1, skew%dim)], equation(:, g) > 0)
          skew%eq(1:skew%n_free(m), m) = equation(skew%free(1:skew%n_free(m), m), g)
        end do
        next = skew%start(1:skew%n)
      end if
    end do
    call check_motions(model, skew)
    allocate(skew%slot(n_equations), skew%component(n_equations))
    skew%slot = 0
    skew%component = 0
    do m = 1, skew%n
      do i = 1, skew%n_free(m)
        skew%slot(skew%eq(i, m)) = m
        skew%component(skew%eq(i, m)) = i
      end do
    end do
    call tie_components(model, equation, tied, skew)
    skew%active = skew%n > 0 .or. skew%n_tied > 0
  end subroutine constraints_set_up

  !> A node takes one motion along a vector, and SPCs in turned systems only normal to it (its
  !> frame's first axis is the motion's direction, exactly).
  subroutine check_motions(model, c)
    type(model_t), intent(in) :: model                 !< resolved model (messages)
    type(node_constraints_t), intent(in) :: c          !< the conditions
    integer :: m, i, j, k
    do m = 1, c%n
      k = 0
      do i = c%start(m), c%start(m + 1) - 1
        if (c%motion(i) == 0) cycle
        if (k > 0) call fatal('implicit: node '//itoa(model%nodes%id(c%node(m)))//' has two '// &
            'motions along vectors (DOF 4; lines '//itoa(model%motions(c%motion(k))%src%line)// &
            ' and '//itoa(model%motions(c%motion(i))%src%line)//')')
        k = i
      end do
      if (k == 0) cycle
      do j = c%start(m), c%start(m + 1) - 1
        if (c%spc(j) == 0) cycle
        if (abs(dot_product(c%dir(:, j), c%dir(:, k))) > ALIGNED) call fatal( &
            'implicit: node '//itoa(model%nodes%id(c%node(m)))//' has a motion along a '// &
            'vector (DOF 4, line '//itoa(model%motions(c%motion(k))%src%line)//') and an SPC '// &
            'in a turned system not normal to it (*BOUNDARY_SPC at line '// &
            itoa(model%spcs(c%spc(j))%src%line)//')')
      end do
    end do
  end subroutine check_motions

  !> The tied components: each tied node's free component i, from its masters' component i
  !> (a fixed master component contributes nothing: it does not move).
  subroutine tie_components(model, equation, tied, c)
    type(model_t), intent(in) :: model                 !< resolved model (messages)
    integer, intent(in) :: equation(:,:)               !< (dim, nodes) equation numbers
    type(tied_nodes_t), intent(in) :: tied             !< the ties
    type(node_constraints_t), intent(inout) :: c       !< tied components set
    integer :: s, i, j, k, n, eq
    allocate(c%tie_slot(size(c%slot)))
    c%tie_slot = 0
    if (tied%n == 0) then
      allocate(c%tie_eq(0), c%tie_start(1), c%tie_target(0), c%tie_weight(0))
      c%tie_start = 1
      return
    end if
    n = 0
    do s = 1, tied%n
      n = n + count(equation(:, tied%slave(s)) > 0)
    end do
    c%n_tied = n
    allocate(c%tie_eq(n), c%tie_start(n + 1), &
             c%tie_target(n*maxval([1, tied%start(2:) - tied%start(:tied%n)])), &
             c%tie_weight(n*maxval([1, tied%start(2:) - tied%start(:tied%n)])))
    k = 0
    c%tie_start(1) = 1
    do s = 1, tied%n
      if (tied%start(s + 1) - tied%start(s) > MAX_TARGETS) call fatal('implicit: node '// &
          itoa(model%nodes%id(tied%slave(s)))//' is tied to '// &
          itoa(tied%start(s + 1) - tied%start(s))//' master nodes (at most '// &
          itoa(MAX_TARGETS)//')')
      do i = 1, c%dim
        eq = equation(i, tied%slave(s))
        if (eq == 0) cycle
        if (c%slot(eq) > 0) call skew_tie(tied%slave(s))
        k = k + 1
        c%tie_eq(k) = eq
        c%tie_slot(eq) = k
        c%tie_start(k + 1) = c%tie_start(k)
        do j = tied%start(s), tied%start(s + 1) - 1
          if (equation(i, tied%master(j)) == 0) cycle
          if (c%slot(equation(i, tied%master(j))) > 0) call skew_tie(tied%master(j))
          c%tie_target(c%tie_start(k + 1)) = equation(i, tied%master(j))
          c%tie_weight(c%tie_start(k + 1)) = tied%weight(j)
          c%tie_start(k + 1) = c%tie_start(k + 1) + 1
        end do
      end do
    end do
  contains
    !> A tied node, or a master of one, with an SPC in a turned system: refused.
    subroutine skew_tie(node)
      integer, intent(in) :: node                     !< mesh node
      call fatal('implicit: node '//itoa(model%nodes%id(node))//' of a tied contact has an '// &
          'SPC in a turned system: the implicit analysis does not take both at a node')
    end subroutine skew_tie
  end subroutine tie_components

  !> The frames at time t: at each node the directions of its SPCs active at t (BT <= t <=
  !> DT), made orthonormal in order (a direction the earlier ones hold is dropped), then
  !> completed by the global axes that are most independent of them.
  subroutine constraints_activate(model, t, skew)
    type(model_t), intent(in) :: model                 !< resolved model
    real(wp), intent(in) :: t                          !< time of the step's end
    type(node_constraints_t), intent(inout) :: skew          !< frames set
    real(wp) :: e(3), q(3, 3)
    integer :: m, c, k, j, d, n
    logical :: whole
    do m = 1, skew%n
      d = skew%n_free(m)                            ! the frame's size: the free components
      q = 0.0_wp
      n = 0
      skew%drive(m) = huge(1.0_wp)
      whole = .false.
      do c = skew%start(m), skew%start(m + 1) - 1      ! a motion first: its axis exactly
        if (skew%motion(c) == 0) cycle
        associate (pm => model%motions(skew%motion(c)))
          if (t < pm%birth .or. t > pm%death) cycle
          e = 0.0_wp
          e(1:d) = skew%dir(skew%free(1:d, m), c)
          call add_direction(e)
          skew%drive(m) = pm%scale*curve_value(model%curves(pm%curve), t)
          whole = pm%dof < 0
        end associate
      end do
      do c = skew%start(m), skew%start(m + 1) - 1
        if (skew%spc(c) == 0) cycle
        associate (spc => model%spcs(skew%spc(c)))
          if (t < spc%birth .or. t > spc%death) cycle
        end associate
        e = 0.0_wp
        e(1:d) = skew%dir(skew%free(1:d, m), c)       ! (the fixed components dropped)
        call add_direction(e)
      end do
      skew%n_fixed(m) = n
      do k = 1, d                                   ! completed by the global axes
        e = 0.0_wp
        e(k) = 1.0_wp
        call add_direction(e)
      end do
      skew%frame(:, :, m) = 0.0_wp
      skew%frame(1:d, 1:d, m) = q(1:d, 1:d)
      if (whole) skew%n_fixed(m) = d                   ! DOF -4: the node moves along e only
    end do
  contains
    !> Append e, made orthogonal to the frame's columns so far, when it is not held by them.
    subroutine add_direction(v)
      real(wp), intent(inout) :: v(3)              !< the direction (changed)
      if (n == d) return
      do j = 1, n
        v = v - dot_product(v, q(:, j))*q(:, j)
      end do
      if (norm2(v) < DEPENDENT) return
      n = n + 1
      q(:, n) = v/norm2(v)
    end subroutine add_direction
  end subroutine constraints_activate

  !> The motions along vectors at the step's start: each driven node moved along its frame's
  !> first axis e to the motion's displacement, u += e (d - e . u) (its other components as
  !> they are), so that Newton keeps the component (du' = 0 there), as the axis motions do.
  pure subroutine constraints_prescribe(c, u)
    type(node_constraints_t), intent(in) :: c          !< constraints (activated)
    real(wp), intent(inout) :: u(:,:)                  !< (dim, nodes) displacements
    real(wp) :: e(3)
    integer :: m, d
    do m = 1, c%n
      if (c%drive(m) == huge(1.0_wp)) cycle
      d = c%n_free(m)
      associate (comps => c%free(1:d, m), node => c%node(m))
        e(1:d) = c%frame(1:d, 1, m)
        u(comps, node) = u(comps, node) + e(1:d)*(c%drive(m) - dot_product(e(1:d), &
                                                                             u(comps, node)))
      end associate
    end do
  end subroutine constraints_prescribe

  !> The external force at the constrained nodes for the work of their reactions (glstat):
  !> at each node with a motion along a vector, the removed components of the internal force
  !> minus the load take the load's place (the reaction and the load together, as at fixed
  !> dofs).
  pure subroutine constraints_reaction(c, internal, g)
    type(node_constraints_t), intent(in) :: c          !< constraints (activated)
    real(wp), intent(in) :: internal(:,:)              !< (dim, nodes) f_int
    real(wp), intent(inout) :: g(:,:)                  !< (dim, nodes) loads; changed there
    real(wp) :: r(3), e(3)
    integer :: m, d, k
    do m = 1, c%n
      if (c%drive(m) == huge(1.0_wp)) cycle
      d = c%n_free(m)
      associate (comps => c%free(1:d, m), node => c%node(m))
        r(1:d) = internal(comps, node) - g(comps, node)
        do k = 1, c%n_fixed(m)
          e(1:d) = c%frame(1:d, k, m)
          g(comps, node) = g(comps, node) + e(1:d)*dot_product(e(1:d), r(1:d))
        end do
      end associate
    end do
  end subroutine constraints_reaction

  !> R' = T^T R: the removed unknowns' residuals 0, every other one the sum of the weights
  !> times the residuals of the equations that spread onto it (spread).
  pure subroutine constraints_residual(c, residual)
    type(node_constraints_t), intent(in) :: c          !< constraints
    real(wp), intent(inout) :: residual(:)             !< (equations) changed in place
    call apply_transpose(c, residual)
  end subroutine constraints_residual

  !> du = T du' (du' the solution of the transformed system): every constrained equation
  !> takes the sum of its targets' du' times their weights.
  pure subroutine constraints_increment(c, du)
    type(node_constraints_t), intent(in) :: c          !< constraints
    real(wp), intent(inout) :: du(:)                   !< (equations) changed in place
    real(wp), allocatable :: original(:)
    real(wp) :: weights(MAX_TARGETS)
    integer :: targets(MAX_TARGETS), eq, n, m, k
    allocate(original, source=du)                      ! (on the heap: equations may be many)
    do m = 1, c%n                                      ! skew nodes' equations
      do k = 1, c%n_free(m)
        eq = c%eq(k, m)
        call spread(c, eq, targets, weights, n)
        du(eq) = sum(weights(1:n)*original(targets(1:n)))
      end do
    end do
    do k = 1, c%n_tied                                 ! tied components
      eq = c%tie_eq(k)
      call spread(c, eq, targets, weights, n)
      du(eq) = sum(weights(1:n)*original(targets(1:n)))
    end do
  end subroutine constraints_increment

  !> v := T^T v.
  pure subroutine apply_transpose(c, v)
    type(node_constraints_t), intent(in) :: c          !< constraints
    real(wp), intent(inout) :: v(:)                    !< (equations)
    real(wp), allocatable :: original(:)
    real(wp) :: weights(MAX_TARGETS)
    integer :: targets(MAX_TARGETS), eq, n, m, k
    allocate(original, source=v)                       ! (on the heap: equations may be many)
    do m = 1, c%n
      v(c%eq(1:c%n_free(m), m)) = 0.0_wp
    end do
    if (c%n_tied > 0) v(c%tie_eq) = 0.0_wp
    do m = 1, c%n
      do k = 1, c%n_free(m)
        eq = c%eq(k, m)
        call spread(c, eq, targets, weights, n)
        v(targets(1:n)) = v(targets(1:n)) + weights(1:n)*original(eq)
      end do
    end do
    do k = 1, c%n_tied
      eq = c%tie_eq(k)
      call spread(c, eq, targets, weights, n)
      v(targets(1:n)) = v(targets(1:n)) + weights(1:n)*original(eq)
    end do
  end subroutine apply_transpose

  !> This rank's entries of T^T K T into b: an entry in a skew node's row (column) spreads
  !> over that node's rows (columns) by the frame, (Q^T K)(q, :) = sum_p Q(p, q) K(p, :);
  !> entries in the rows or columns of fixed components are left out and rank 0 adds their
  !> unit diagonal. A lower-triangle matrix (symmetric storage) is spread as the full one (an
  !> off-diagonal entry stands for its mirror too) and b keeps the lower triangle. The
  !> positions depend on a's only, so b's pattern_id is a's (the solver's analysis is kept
  !> while a's pattern is).
  subroutine constraints_matrix(skew, a, b)
    type(node_constraints_t), intent(in) :: skew             !< frames
    type(coo_matrix_t), intent(in) :: a                !< K, this rank's entries
    type(coo_matrix_t), intent(inout) :: b             !< T^T K T, this rank's entries
    integer :: rows(MAX_TARGETS), cols(MAX_TARGETS), nr, nc, i, j, m, k
    real(wp) :: wr(MAX_TARGETS), wc(MAX_TARGETS), block(MAX_TARGETS, MAX_TARGETS)
    integer(i8) :: e
    logical :: lower
    lower = a%storage == STORAGE_LOWER
    call coo_init(b, a%n, a%nnz + int(skew%n*skew%dim, i8))
    do e = 1, a%nnz
      call spread(skew, a%row(e), rows, wr, nr)
      call spread(skew, a%col(e), cols, wc, nc)
      do j = 1, nc
        do i = 1, nr
          block(i, j) = wr(i)*wc(j)*a%val(e)
        end do
      end do
      call coo_add_rectangle(b, rows(1:nr), cols(1:nc), block(1:nr, 1:nc), lower)
      if (lower .and. a%row(e) /= a%col(e)) &                ! its mirror
        call coo_add_rectangle(b, cols(1:nc), rows(1:nr), transpose(block(1:nr, 1:nc)), lower)
    end do
    if (comm_rank() == 0) then                           ! the removed unknowns
      do m = 1, skew%n
        do k = 1, skew%n_fixed(m)
          call coo_add_rectangle(b, skew%eq(k:k, m), skew%eq(k:k, m), &
                                 reshape([1.0_wp], [1, 1]), lower)
        end do
      end do
      do k = 1, skew%n_tied
        call coo_add_rectangle(b, skew%tie_eq(k:k), skew%tie_eq(k:k), &
                               reshape([1.0_wp], [1, 1]), lower)
      end do
    end if
    b%pattern_id = a%pattern_id
  end subroutine constraints_matrix

  !> The transformed rows (or columns) an equation spreads over, with their weights (a row
  !> of T): the equation itself, weight 1, away from the constraints; at a skew node the free
  !> components q of its frame with Q(p, q) (p the equation's component there); for a tied
  !> component its masters' equations with their weights.
  pure subroutine spread(skew, eq, targets, weights, count)
    type(node_constraints_t), intent(in) :: skew      !< constraints
    integer, intent(in) :: eq                         !< the equation of a's entry
    integer, intent(out) :: targets(MAX_TARGETS)      !< equations of b
    real(wp), intent(out) :: weights(MAX_TARGETS)     !< weights
    integer, intent(out) :: count                     !< how many
    integer :: m, p, q, k
    m = skew%slot(eq)
    if (m > 0) then
      p = skew%component(eq)
      count = 0
      do q = skew%n_fixed(m) + 1, skew%n_free(m)
        count = count + 1
        targets(count) = skew%eq(q, m)
        weights(count) = skew%frame(p, q, m)
      end do
      return
    end if
    k = 0
    if (allocated(skew%tie_slot)) k = skew%tie_slot(eq)
    if (k > 0) then
      count = skew%tie_start(k + 1) - skew%tie_start(k)
      targets(1:count) = skew%tie_target(skew%tie_start(k):skew%tie_start(k + 1) - 1)
      weights(1:count) = skew%tie_weight(skew%tie_start(k):skew%tie_start(k + 1) - 1)
      return
    end if
    count = 1
    targets(1) = eq
    weights(1) = 1.0_wp
  end subroutine spread

end module mefem_implicit_constraints
