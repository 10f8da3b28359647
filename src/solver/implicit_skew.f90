!> SPCs in turned local systems (CID, skew conditions) in the implicit analysis (doc/theory.md
!> 6.7): at a node with such conditions the Newton system is written in a node frame Q whose
!> first columns are the fixed local directions e (made orthonormal) and whose others complete
!> it, u = Q u'. With T the block diagonal of the node frames (identity elsewhere) the solver
!> takes T^T K T and T^T R, the rows and columns of the fixed components replaced by the
!> identity and their residuals by 0 (du'_e = 0: the condition holds exactly, as a global
!> SPC's does), and the increment goes back as du = T du'. T is orthogonal, so norms and the
!> energy du.R are those of the global system. The frame acts on the node's free global
!> components: a global dof fixed by an SPC there (a local axis that is a global one, or
!> another SPC) stays fixed, and the directions lose their components along it (as in the
!> explicit analysis); a node with a driven (prescribed) dof is refused. The conditions of an
!> SPC take effect while BT <= t <= DT (the step's end time), as the global ones do.
module mefem_implicit_skew
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: fatal
  use mefem_strings, only: itoa
  use mefem_model, only: model_t
  use mefem_boundary_conditions, only: target_nodes
  use mefem_sparse_assembly, only: coo_matrix_t, coo_init, coo_add_rectangle, STORAGE_LOWER
  use mefem_comm, only: comm_rank
  implicit none
  private

  public :: skew_nodes_t, implicit_skew_set_up, implicit_skew_activate
  public :: implicit_skew_residual, implicit_skew_matrix, implicit_skew_increment

  !> length below which a direction is held by the node's earlier ones already
  real(wp), parameter :: DEPENDENT = 1.0e-8_wp

  !> The nodes with skew conditions and their frames.
  type :: skew_nodes_t
    integer :: n = 0                               !< nodes
    integer :: dim = 3
    integer, allocatable :: node(:)                !< (n) mesh node
    integer, allocatable :: n_free(:)              !< (n) its free global components
    integer, allocatable :: free(:,:)              !< (dim, n) which (1 x, 2 y, 3 z)
    integer, allocatable :: eq(:,:)                !< (dim, n) their equations
    integer, allocatable :: start(:)               !< (n + 1) its conditions in spc, dir
    integer, allocatable :: spc(:)                 !< the SPC of each condition
    real(wp), allocatable :: dir(:,:)              !< (3, conditions) its direction
    real(wp), allocatable :: frame(:,:,:)          !< (dim, dim, n) Q on the free components
                                                   !< (n_free x n_free), fixed directions first
    integer, allocatable :: n_fixed(:)             !< (n) fixed components (active now)
    integer, allocatable :: slot(:)                !< (equations) node of an equation, or 0
    integer, allocatable :: component(:)           !< (equations) its component there
  end type skew_nodes_t

contains

  !> The nodes of the SPCs with skew directions (spc%n_skew > 0), their conditions in deck
  !> order, their free components and equations; a node with a driven dof is an error.
  subroutine implicit_skew_set_up(model, equation, n_equations, driven, skew)
    type(model_t), intent(in) :: model                 !< resolved model
    integer, intent(in) :: equation(:,:)               !< (dim, nodes) equation numbers
    integer, intent(in) :: n_equations                 !< number of equations
    logical, intent(in) :: driven(:,:)                 !< (dim, mesh nodes) prescribed dofs
    type(skew_nodes_t), intent(out) :: skew            !< the nodes
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
      if (pass == 1) then
        skew%n = count(count_at > 0)
        skew%node = pack([(g, g = 1, size(count_at))], count_at > 0)
        allocate(slot_of(size(count_at)), skew%start(skew%n + 1), skew%spc(total), &
                 skew%dir(3, total), skew%eq(skew%dim, skew%n), skew%free(skew%dim, skew%n), &
                 skew%n_free(skew%n), skew%frame(skew%dim, skew%dim, skew%n), &
                 skew%n_fixed(skew%n))
        slot_of = 0
        skew%start(1) = 1
        skew%eq = 0
        skew%free = 0
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
    allocate(skew%slot(n_equations), skew%component(n_equations))
    skew%slot = 0
    skew%component = 0
    do m = 1, skew%n
      do i = 1, skew%n_free(m)
        skew%slot(skew%eq(i, m)) = m
        skew%component(skew%eq(i, m)) = i
      end do
    end do
  end subroutine implicit_skew_set_up

  !> The frames at time t: at each node the directions of its SPCs active at t (BT <= t <=
  !> DT), made orthonormal in order (a direction the earlier ones hold is dropped), then
  !> completed by the global axes that are most independent of them.
  subroutine implicit_skew_activate(model, t, skew)
    type(model_t), intent(in) :: model                 !< resolved model
    real(wp), intent(in) :: t                          !< time of the step's end
    type(skew_nodes_t), intent(inout) :: skew          !< frames set
    real(wp) :: e(3), q(3, 3)
    integer :: m, c, k, j, d, n
    do m = 1, skew%n
      d = skew%n_free(m)                            ! the frame's size: the free components
      q = 0.0_wp
      n = 0
      do c = skew%start(m), skew%start(m + 1) - 1
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
  end subroutine implicit_skew_activate

  !> R' = T^T R, the fixed components zeroed.
  pure subroutine implicit_skew_residual(skew, residual)
    type(skew_nodes_t), intent(in) :: skew             !< frames
    real(wp), intent(inout) :: residual(:)             !< (equations) changed in place
    real(wp) :: r(3)
    integer :: m, d
    do m = 1, skew%n
      d = skew%n_free(m)
      r(1:d) = matmul(transpose(skew%frame(1:d, 1:d, m)), residual(skew%eq(1:d, m)))
      r(1:skew%n_fixed(m)) = 0.0_wp
      residual(skew%eq(1:d, m)) = r(1:d)
    end do
  end subroutine implicit_skew_residual

  !> du = T du' (du' the solution of the transformed system).
  pure subroutine implicit_skew_increment(skew, du)
    type(skew_nodes_t), intent(in) :: skew             !< frames
    real(wp), intent(inout) :: du(:)                   !< (equations) changed in place
    integer :: m, d
    do m = 1, skew%n
      d = skew%n_free(m)
      du(skew%eq(1:d, m)) = matmul(skew%frame(1:d, 1:d, m), du(skew%eq(1:d, m)))
    end do
  end subroutine implicit_skew_increment

  !> This rank's entries of T^T K T into b: an entry in a skew node's row (column) spreads
  !> over that node's rows (columns) by the frame, (Q^T K)(q, :) = sum_p Q(p, q) K(p, :);
  !> entries in the rows or columns of fixed components are left out and rank 0 adds their
  !> unit diagonal. A lower-triangle matrix (symmetric storage) is spread as the full one (an
  !> off-diagonal entry stands for its mirror too) and b keeps the lower triangle. The
  !> positions depend on a's only, so b's pattern_id is a's (the solver's analysis is kept
  !> while a's pattern is).
  subroutine implicit_skew_matrix(skew, a, b)
    type(skew_nodes_t), intent(in) :: skew             !< frames
    type(coo_matrix_t), intent(in) :: a                !< K, this rank's entries
    type(coo_matrix_t), intent(inout) :: b             !< T^T K T, this rank's entries
    integer :: rows(3), cols(3), nr, nc, i, j, m, k
    real(wp) :: wr(3), wc(3), block(3, 3)
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
    if (comm_rank() == 0) then
      do m = 1, skew%n
        do k = 1, skew%n_fixed(m)
          call coo_add_rectangle(b, skew%eq(k:k, m), skew%eq(k:k, m), &
                                 reshape([1.0_wp], [1, 1]), lower)
        end do
      end do
    end if
    b%pattern_id = a%pattern_id
  end subroutine implicit_skew_matrix

  !> The transformed rows (or columns) an equation spreads over, with their weights: the
  !> equation itself, weight 1, away from skew nodes; at a skew node the free components q
  !> of its frame with Q(p, q) (p the equation's global component).
  pure subroutine spread(skew, eq, targets, weights, count)
    type(skew_nodes_t), intent(in) :: skew            !< frames
    integer, intent(in) :: eq                         !< the equation of a's entry
    integer, intent(out) :: targets(3)                !< equations of b
    real(wp), intent(out) :: weights(3)               !< weights
    integer, intent(out) :: count                     !< how many
    integer :: m, p, q
    m = skew%slot(eq)
    if (m == 0) then
      count = 1
      targets(1) = eq
      weights(1) = 1.0_wp
      return
    end if
    p = skew%component(eq)
    count = 0
    do q = skew%n_fixed(m) + 1, skew%n_free(m)
      count = count + 1
      targets(count) = skew%eq(q, m)
      weights(count) = skew%frame(p, q, m)
    end do
  end subroutine spread

end module mefem_implicit_skew
