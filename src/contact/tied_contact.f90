!> Tied contacts, *CONTACT_TIED_SURFACE_TO_SURFACE and *CONTACT_TIED_NODES_TO_SURFACE (and
!> their _OFFSET and _CONSTRAINED_OFFSET forms): the geometric part, done once when the
!> analysis starts (doc/theory.md 10.12). Every tied SURFA node s moves with a combination of
!> SURFB nodes, u_s = sum_c w_sc u_c (sum_c w_sc = 1); the initial gap is kept (no node is
!> moved). The weights:
!>  - dual mortar (a SURFA node whose facets facing SURFB are covered entirely): with the
!>    mortar integrals of 10.3 over the overlaps of SURFA's facets (quadrilaterals as the
!>    four triangles of 10.2) with the SURFB facets that face them within the tolerance,
!>    w_sc = int Phi_s N_c / int N_s, Phi_s = (dim+1) N_s - 1 on each facet the dual basis
!>    (int Phi_s N_b = delta_sb int N_s). The constraint then reproduces every linear field and
!>    passes the slave forces of a uniform traction on as the master's consistent forces: the
!>    tie passes the patch test across non-matching meshes;
!>  - projection (the other SURFA nodes within the tolerance of a SURFB facet, e.g. at the
!>    border of the interface, and node-set nodes on no SURFA facet): the barycentric
!>    coordinates of the node's normal projection on the nearest facet (a quadrilateral cut
!>    into N1 N2 N3 and N1 N3 N4; coordinates >= -EDGE_TOLERANCE, clamped onto it).
!> SURFA nodes that are SURFB nodes too (shared) are joined already and not tied. The tolerance
!> is -SST when SST < 0, else DEFAULT_TOLERANCE times the facet's size (square
!> root of its area; 2D: its length): the largest normal distance of a tied node (projection)
!> or facet centroid (mortar) from the SURFB facet. The explicit analysis enforces the ties
!> kinematically (mefem_explicit_ties). The data are the same on every rank (replicated).
module mefem_tied_contact
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa
  use mefem_vector_math, only: cross
  use mefem_model, only: model_t, SURFACE_NODE_SET, TIEBREAK_NONE
  use mefem_id_map, only: sort_with_index
  use mefem_contact_surfaces, only: contact_surface_t, contact_search_t, contact_surface_build, &
                                    contact_search_build, contact_surface_triangulate, &
                                    contact_facet_area_vector
  use mefem_mortar_segmentation, only: mortar_segment_pair_2d, mortar_triangle_pair_3d
  implicit none
  private

  public :: tied_contact_build

  real(wp), parameter :: DEFAULT_TOLERANCE = 0.1_wp  !< normal distance / facet size tied
  real(wp), parameter :: EDGE_TOLERANCE = 0.01_wp    !< barycentric overshoot still tied
  real(wp), parameter :: FACING_COSINE = 0.25_wp     !< tied facets face each other (cos)
  real(wp), parameter :: COVERED = 1.0_wp - 1.0e-9_wp !< covered share of a facet: whole

  !> The tied nodes of all tied contacts: node s = slave(i) moves with the master nodes
  !> master(start(i):start(i+1)-1) and their weights.
  type, public :: tied_nodes_t
    integer :: n = 0                               !< tied nodes
    integer, allocatable :: slave(:)               !< (n) mesh node, ascending
    integer, allocatable :: start(:)               !< (n + 1) its entries
    integer, allocatable :: master(:)              !< (entries) master mesh node
    integer, allocatable :: master_slot(:)         !< (entries) its position in master_node
    real(wp), allocatable :: weight(:)             !< (entries) w_sc
    integer, allocatable :: tie(:)                 !< (n) its contact (index in model%ties)
    logical, allocatable :: dual(:)                !< (n) dual mortar weights (else projection)
    integer :: nmaster = 0                         !< distinct master nodes
    integer, allocatable :: master_node(:)         !< (nmaster) mesh nodes, ascending
    integer, allocatable :: entry_start(:)         !< (nmaster + 1) master j's entries
    integer, allocatable :: entry_slave(:)         !< tied node i of each entry (ascending)
    real(wp), allocatable :: entry_weight(:)       !< its weight
    integer, allocatable :: untied(:)              !< (ties) SURFA nodes left untied
    integer, allocatable :: first_untied(:)        !< (ties) the first of them (mesh node)
    real(wp), allocatable :: tolerance(:)          !< (ties) the tolerance (-SST), or 0
    ! tiebreak (contact_t%tiebreak): a tied node is held until its tie force fails it
    real(wp), allocatable :: area(:)               !< (n) its share of the SURFA facets' area
                                                   !< (reference; 0 for a node on none)
    logical, allocatable :: held(:)                !< (n) still tied (always, without failure)
    integer, allocatable :: slave_id(:)            !< (n) the node's id (messages)
    logical :: tiebreak = .false.                  !< some tie can fail
    integer, allocatable :: fail_kind(:)           !< (ties) TIEBREAK_* of each tie
    real(wp), allocatable :: fail_limits(:,:)      !< (4, ties) normal and shear limits, their
                                                   !< exponents (contact_t fail_*)
    integer, allocatable :: companion(:)           !< (ties) the contact taking over, or 0
  end type tied_nodes_t

  !> A growing list of (slave, master, weight) triplets.
  type :: triplets_t
    integer :: n = 0
    integer, allocatable :: slave(:), master(:), tie(:)
    real(wp), allocatable :: weight(:)
    logical, allocatable :: dual(:)
  end type triplets_t

contains

  !> The tied nodes of every tied contact of the model (model%ties). Fails (status) on a
  !> surface that cannot be built, a node tied by two contacts, or a tied node that is a
  !> master node of a tie.
  subroutine tied_contact_build(model, tied, status)
    type(model_t), intent(in) :: model                !< resolved model
    type(tied_nodes_t), intent(out) :: tied           !< the tied nodes
    type(status_t), intent(out) :: status             !< failure and message
    type(triplets_t) :: list
    integer, allocatable :: order(:), keys(:), tie_of(:), slot(:)
    logical, allocatable :: is_master(:)
    real(wp), allocatable :: node_area(:)
    integer :: k, i, j, e, c, g, n
    allocate(tied%untied(model%n_ties), tied%first_untied(model%n_ties), &
             tied%tolerance(model%n_ties))
    allocate(list%slave(64), list%master(64), list%tie(64), list%weight(64), list%dual(64))
    allocate(node_area(model%nodes%n))
    node_area = 0.0_wp
    do k = 1, model%n_ties
      call tie_one(model, k, tied, list, node_area, status)
      if (.not. status%ok) return
    end do
    ! the triplets by slave node (stable: each node's entries in the order found)
    keys = list%slave(1:list%n)
    order = [(i, i = 1, list%n)]
    call sort_with_index(keys, order)
    ! one tie per node, and no node both tied and a master of a tie
    allocate(tie_of(model%nodes%n), is_master(model%nodes%n))
    tie_of = 0
    is_master = .false.
    is_master(list%master(1:list%n)) = .true.
    do e = 1, list%n
      i = order(e)
      g = list%slave(i)
      if (tie_of(g) > 0 .and. tie_of(g) /= list%tie(i)) then
        call fail('node '//itoa(model%nodes%id(g))//' is tied by '//who(model, tie_of(g))// &
            ' and by '//who(model, list%tie(i))//' (a node may be tied once)')
        return
      end if
      tie_of(g) = list%tie(i)
      if (is_master(g)) then
        call fail(who(model, list%tie(i))//': node '//itoa(model%nodes%id(g))//' is tied '// &
            'and is a master node of a tie (chains of ties are not supported: tie both '// &
            'surfaces to the same master surface)')
        return
      end if
    end do
    ! tied nodes ascending, their entries
    n = count(tie_of > 0)
    tied%n = n
    tied%slave = pack([(g, g = 1, model%nodes%n)], tie_of > 0)
    tied%tie = tie_of(tied%slave)
    tied%area = node_area(tied%slave)
    tied%slave_id = model%nodes%id(tied%slave)
    allocate(tied%held(n))
    tied%held = .true.
    tied%fail_kind = [(model%ties(k)%tiebreak, k = 1, model%n_ties)]
    tied%companion = [(model%ties(k)%companion, k = 1, model%n_ties)]
    allocate(tied%fail_limits(4, model%n_ties))
    do k = 1, model%n_ties
      tied%fail_limits(:, k) = [model%ties(k)%fail_normal, model%ties(k)%fail_shear, &
                                model%ties(k)%fail_exponent_normal, &
                                model%ties(k)%fail_exponent_shear]
    end do
    tied%tiebreak = any(tied%fail_kind /= TIEBREAK_NONE)
    allocate(tied%start(n + 1), tied%dual(n))
    tied%master = list%master(order)
    tied%weight = list%weight(order)
    tied%start(1) = 1
    i = 0
    do e = 1, list%n
      if (e == 1) then
        i = 1
      else if (list%slave(order(e)) /= list%slave(order(e - 1))) then
        i = i + 1
        tied%start(i) = e
      end if
      tied%dual(i) = list%dual(order(e))
    end do
    tied%start(n + 1) = list%n + 1
    ! the distinct master nodes and, per master, its entries (tied nodes ascending)
    tied%master_node = pack([(g, g = 1, model%nodes%n)], is_master)
    tied%nmaster = size(tied%master_node)
    allocate(slot(model%nodes%n))
    slot = 0
    slot(tied%master_node) = [(j, j = 1, tied%nmaster)]
    tied%master_slot = slot(tied%master)
    allocate(tied%entry_start(tied%nmaster + 1))
    tied%entry_start = 0
    do e = 1, list%n
      c = tied%master_slot(e)
      tied%entry_start(c + 1) = tied%entry_start(c + 1) + 1
    end do
    tied%entry_start(1) = 1
    do c = 1, tied%nmaster
      tied%entry_start(c + 1) = tied%entry_start(c + 1) + tied%entry_start(c)
    end do
    allocate(tied%entry_slave(list%n), tied%entry_weight(list%n))
    block
      integer, allocatable :: next(:)
      next = tied%entry_start(1:tied%nmaster)
      do i = 1, n
        do e = tied%start(i), tied%start(i + 1) - 1
          c = tied%master_slot(e)
          tied%entry_slave(next(c)) = i
          tied%entry_weight(next(c)) = tied%weight(e)
          next(c) = next(c) + 1
        end do
      end do
    end block
    status%ok = .true.
  contains
    !> Record a failure.
    subroutine fail(message)
      character(len=*), intent(in) :: message         !< what is wrong
      status%ok = .false.
      status%message = message
    end subroutine fail
  end subroutine tied_contact_build

  !> The tied nodes of tied contact k as triplets (slave, master, weight) appended to list:
  !> dual mortar weights for the SURFA nodes whose facets are covered, projection weights
  !> for the others within the tolerance; its count of untied SURFA nodes.
  subroutine tie_one(model, k, tied, list, node_area, status)
    type(model_t), intent(in) :: model                !< resolved model
    integer, intent(in) :: k                          !< the contact (model%ties)
    type(tied_nodes_t), intent(inout) :: tied         !< untied counts, tolerances
    type(triplets_t), intent(inout) :: list           !< triplets appended
    real(wp), intent(inout) :: node_area(:)           !< (mesh nodes) SURFA facet area shares
                                                      !< added
    type(status_t), intent(out) :: status             !< failure and message
    type(contact_surface_t) :: slave, master
    integer, allocatable :: slaves(:), local_of(:)
    real(wp), allocatable :: facet_tolerance(:)
    logical, allocatable :: done(:)
    logical :: have_facets
    integer :: i
    associate (c => model%ties(k))
      call contact_surface_build(model, c%surf_b_type, c%surf_b, master, status, &
                                 who(model, k)//' SURFB')
      if (.not. status%ok) return
      call contact_surface_build(model, c%surf_a_type, c%surf_a, slave, status, &
                                 who(model, k)//' SURFA')
      have_facets = status%ok
      if (c%surf_a_type == SURFACE_NODE_SET) then
        slaves = model%sets(c%surf_a)%members        ! (nodes on no facet: projection only)
        status%ok = .true.                          ! (a node set need not span facets)
      else
        if (.not. status%ok) return
        slaves = slave%nodes
      end if
      tied%tolerance(k) = 0.0_wp
      if (c%sast < 0.0_wp) tied%tolerance(k) = -c%sast
    end associate
    ! a node of both surfaces (bodies that share nodes there) is joined already: not tied
    block
      logical, allocatable :: on_master(:)
      allocate(on_master(model%nodes%n))
      on_master = .false.
      on_master(master%nodes) = .true.
      slaves = pack(slaves, .not. on_master(slaves))
    end block
    call facet_tolerances(model, master, tied%tolerance(k), facet_tolerance)
    ! dual mortar weights of the slave facets' nodes
    allocate(local_of(model%nodes%n), done(size(slaves)))
    local_of = 0
    local_of(slaves) = [(i, i = 1, size(slaves))]
    done = .false.
    if (have_facets) then
      call contact_surface_triangulate(slave)
      call dual_weights(model, slave, master, facet_tolerance, list, k, slaves, local_of, done)
      call add_area_shares(model, slave, node_area)
    end if
    ! projections of the others
    call projections(model, master, facet_tolerance, slaves, done, list, k, &
                     tied%untied(k), tied%first_untied(k))
    status%ok = .true.
  end subroutine tie_one

  !> Each node's share of the area of the (triangulated) SURFA facets: a facet's weighted area
  !> over its vertices, summed (2D: the length of the edges; reference configuration).
  subroutine add_area_shares(model, slave, node_area)
    type(model_t), intent(in) :: model                !< the model (coordinates)
    type(contact_surface_t), intent(in) :: slave      !< SURFA facets (triangulated)
    real(wp), intent(inout) :: node_area(:)           !< (mesh nodes) shares added
    real(wp) :: share
    integer :: sf, nv
    nv = slave%dim
    do sf = 1, slave%nfacet
      share = slave%weight(sf)*norm2(contact_facet_area_vector(slave, sf, model%nodes%x))/ &
              real(nv, wp)
      node_area(slave%facets(1:nv, sf)) = node_area(slave%facets(1:nv, sf)) + share
    end do
  end subroutine add_area_shares

  !> Each SURFB facet's tolerance: the given one (-SST), or DEFAULT_TOLERANCE times its size
  !> (square root of its area; 2D: its length).
  subroutine facet_tolerances(model, master, tolerance, facet_tolerance)
    type(model_t), intent(in) :: model                !< the model (coordinates)
    type(contact_surface_t), intent(in) :: master     !< SURFB facets
    real(wp), intent(in) :: tolerance                 !< -SST, or 0 for the default
    real(wp), allocatable, intent(out) :: facet_tolerance(:) !< (facets)
    integer :: f
    allocate(facet_tolerance(master%nfacet))
    do f = 1, master%nfacet
      if (tolerance > 0.0_wp) then
        facet_tolerance(f) = tolerance
      else if (master%dim == 2) then
        facet_tolerance(f) = DEFAULT_TOLERANCE*norm2(contact_facet_area_vector(master, f, &
                                                                               model%nodes%x))
      else
        facet_tolerance(f) = DEFAULT_TOLERANCE*sqrt(norm2(contact_facet_area_vector(master, &
                                                                   f, model%nodes%x)))
      end if
    end do
  end subroutine facet_tolerances

  !> Dual mortar weights (module header) of the SURFA nodes whose facets the SURFB facets
  !> cover; those nodes are marked done and their triplets appended.
  subroutine dual_weights(model, slave, master, facet_tolerance, list, k, slaves, local_of, &
                          done)
    type(model_t), intent(in) :: model                !< the model (coordinates)
    type(contact_surface_t), intent(in) :: slave      !< SURFA facets (triangulated)
    type(contact_surface_t), intent(in) :: master     !< SURFB facets
    real(wp), intent(in) :: facet_tolerance(:)        !< (master facets)
    type(triplets_t), intent(inout) :: list           !< triplets appended
    integer, intent(in) :: k                          !< the contact
    integer, intent(in) :: slaves(:)                  !< SURFA nodes
    integer, intent(in) :: local_of(:)                !< (mesh nodes) position among the slaves
    logical, intent(inout) :: done(:)                 !< (slaves) tied here
    type(contact_search_t) :: search
    integer, allocatable :: candidates(:,:), head(:), next(:), node_of(:)
    real(wp), allocatable :: weight(:), integral(:), area(:), overlapped(:)
    logical, allocatable :: allow(:)
    real(wp) :: n_ab(3, 3), n_ac(3, 4), overlap, xs(3, 3), xm(3, 4), a(3), n_s(3), n_m(3)
    real(wp) :: centre(3), dual(4)
    integer :: ncandidate, q, sf, mf, i, b, cc, nv, nm, dim, node, e, entries
    dim = model%dimension
    nv = dim                                          ! slave facet vertices (triangle / edge)
    allocate(integral(size(done)), allow(size(done)), head(size(done)))
    integral = 0.0_wp
    head = 0
    allocate(next(64), node_of(64), weight(64))
    entries = 0
    ! each slave facet's area (weighted), and the part of it the partners cover
    allocate(area(slave%nfacet), overlapped(slave%nfacet))
    do sf = 1, slave%nfacet
      area(sf) = slave%weight(sf)*norm2(contact_facet_area_vector(slave, sf, model%nodes%x))
    end do
    overlapped = 0.0_wp
    call contact_search_build(search, slave, master, model%nodes%x, maxval(facet_tolerance), &
                              candidates, ncandidate)
    do q = 1, ncandidate
      sf = candidates(1, q)
      mf = candidates(2, q)
      ! partners: facing each other, the slave facet's centroid within the tolerance
      a = contact_facet_area_vector(slave, sf, model%nodes%x)
      if (.not. norm2(a) > 0.0_wp) cycle
      n_s = a/norm2(a)
      a = contact_facet_area_vector(master, mf, model%nodes%x)
      if (.not. norm2(a) > 0.0_wp) cycle
      n_m = a/norm2(a)
      if (dot_product(n_s, n_m) > -FACING_COSINE) cycle
      centre = 0.0_wp
      do i = 1, nv
        centre = centre + model%nodes%x(:, slave%facets(i, sf))/real(nv, wp)
      end do
      if (abs(dot_product(centre - model%nodes%x(:, master%facets(1, mf)), n_m)) > &
          facet_tolerance(mf)) cycle
      nm = master%nvertex(mf)
      if (dim == 2) then
        n_ab = 0.0_wp
        n_ac = 0.0_wp
        call mortar_segment_pair_2d(model%nodes%x(1:2, slave%facets(1:2, sf)), &
                                    model%nodes%x(1:2, master%facets(1:2, mf)), &
                                    n_ab(1:2, 1:2), n_ac(1:2, 1:2), overlap)
      else
        do i = 1, 3
          xs(:, i) = model%nodes%x(:, slave%facets(i, sf))
        end do
        xm = 0.0_wp
        do i = 1, nm
          xm(:, i) = model%nodes%x(:, master%facets(i, mf))
        end do
        call mortar_triangle_pair_3d(xs, xm, nm, n_ab, n_ac, overlap)
      end if
      if (.not. overlap > 0.0_wp) cycle
      overlapped(sf) = overlapped(sf) + slave%weight(sf)*overlap
      ! per slave vertex: int N_s (its covered share) and int Phi_s N_c, Phi_s = (dim+1) N_s
      ! - sum_b N_b on the facet (the dual basis: int Phi_s N_b = delta_sb int N_s)
      do i = 1, nv
        node = local_of(slave%facets(i, sf))
        if (node == 0) cycle
        integral(node) = integral(node) + slave%weight(sf)*sum(n_ab(i, 1:nv))
        do cc = 1, nm
          dual(cc) = real(dim + 1, wp)*n_ac(i, cc)
          do b = 1, nv
            dual(cc) = dual(cc) - n_ac(b, cc)
          end do
          call add_entry(node, master%facets(cc, mf), slave%weight(sf)*dual(cc))
        end do
      end do
    end do
    ! the nodes whose partnered facets (those with an overlap) are all covered entirely: the
    ! weights int Phi_s N_c / int N_s (the dual basis on those facets), masters merged
    allow = .true.
    do sf = 1, slave%nfacet
      if (overlapped(sf) <= 0.0_wp .or. overlapped(sf) >= COVERED*area(sf)) cycle
      do i = 1, nv
        node = local_of(slave%facets(i, sf))
        if (node > 0) allow(node) = .false.
      end do
    end do
    do node = 1, size(done)
      if (head(node) == 0 .or. .not. allow(node) .or. .not. integral(node) > 0.0_wp) cycle
      done(node) = .true.
      e = head(node)
      do while (e > 0)
        call append(list, slaves(node), node_of(e), weight(e)/integral(node), k, .true.)
        e = next(e)
      end do
    end do
  contains
    !> Add w to the (slave node, master) entry, in the order masters were first met.
    subroutine add_entry(s_node, m_node, w)
      integer, intent(in) :: s_node, m_node           !< slave (local), master (mesh)
      real(wp), intent(in) :: w                       !< weight to add
      integer :: e2, last
      e2 = head(s_node)
      last = 0
      do while (e2 > 0)
        if (node_of(e2) == m_node) then
          weight(e2) = weight(e2) + w
          return
        end if
        last = e2
        e2 = next(e2)
      end do
      entries = entries + 1
      if (entries > size(next)) then
        next = [next, [(0, e2 = 1, size(next))]]
        node_of = [node_of, [(0, e2 = 1, size(node_of))]]
        weight = [weight, [(0.0_wp, e2 = 1, size(weight))]]
      end if
      next(entries) = 0
      node_of(entries) = m_node
      weight(entries) = w
      if (last == 0) then
        head(s_node) = entries
      else
        next(last) = entries
      end if
    end subroutine add_entry
  end subroutine dual_weights

  !> Projection weights (module header) of the slave nodes not done, against the SURFB facets
  !> (quadrilaterals cut into N1 N2 N3 and N1 N3 N4); the others counted as untied.
  subroutine projections(model, master, facet_tolerance, slaves, done, list, k, untied, &
                         first_untied)
    type(model_t), intent(in) :: model                !< the model (coordinates)
    type(contact_surface_t), intent(in) :: master     !< SURFB facets
    real(wp), intent(in) :: facet_tolerance(:)        !< (master facets)
    integer, intent(in) :: slaves(:)                  !< SURFA nodes
    logical, intent(in) :: done(:)                    !< (slaves) tied by dual weights
    type(triplets_t), intent(inout) :: list           !< triplets appended
    integer, intent(in) :: k                          !< the contact
    integer, intent(out) :: untied, first_untied      !< nodes left untied, the first
    type(contact_surface_t) :: points, pieces
    type(contact_search_t) :: search
    integer, allocatable :: candidates(:,:), piece_facet(:), todo(:)
    real(wp) :: best_distance, best_inside, distance, lambda(3), inside, best_lambda(3)
    integer :: ncandidate, i, p, q, dim, nv, best, first, f, m
    dim = model%dimension
    untied = 0
    first_untied = 0
    todo = pack(slaves, .not. done)
    if (size(todo) == 0) return
    ! the pieces: triangles (2D: edges)
    m = 0
    do f = 1, master%nfacet
      m = m + merge(2, 1, master%nvertex(f) == 4)
    end do
    pieces%dim = master%dim
    pieces%nfacet = m
    allocate(pieces%facets(4, m), pieces%nvertex(m), piece_facet(m))
    pieces%facets = 0
    m = 0
    do f = 1, master%nfacet
      m = m + 1
      pieces%nvertex(m) = merge(2, 3, dim == 2)
      pieces%facets(1:pieces%nvertex(m), m) = master%facets(1:pieces%nvertex(m), f)
      piece_facet(m) = f
      if (master%nvertex(f) == 4) then
        m = m + 1
        pieces%nvertex(m) = 3
        pieces%facets(1:3, m) = [master%facets(1, f), master%facets(3, f), master%facets(4, f)]
        piece_facet(m) = f
      end if
    end do
    nv = merge(2, 3, dim == 2)
    ! the nodes as one-point facets; candidates: pieces whose boxes, enlarged by the largest
    ! tolerance, hold the node
    points%dim = dim
    points%nfacet = size(todo)
    allocate(points%facets(4, size(todo)), points%nvertex(size(todo)))
    points%facets = 0
    points%facets(1, :) = todo
    points%nvertex = 1
    call contact_search_build(search, points, pieces, model%nodes%x, maxval(facet_tolerance), &
                              candidates, ncandidate)
    first = 1
    do i = 1, size(todo)
      best = 0
      best_distance = huge(1.0_wp)
      best_inside = -huge(1.0_wp)
      do q = first, ncandidate
        if (candidates(1, q) /= i) exit
        p = candidates(2, q)
        call project(model%nodes%x(:, todo(i)), model%nodes%x, pieces, p, dim, distance, &
                     lambda)
        inside = minval(lambda(1:nv))
        if (inside < -EDGE_TOLERANCE .or. distance > facet_tolerance(piece_facet(p))) cycle
        if (distance < best_distance .or. (distance == best_distance .and. &
                                           inside > best_inside)) then
          best = p
          best_distance = distance
          best_inside = inside
          best_lambda = lambda
        end if
      end do
      do while (first <= ncandidate)
        if (candidates(1, first) /= i) exit
        first = first + 1
      end do
      if (best == 0) then
        untied = untied + 1
        if (first_untied == 0) first_untied = todo(i)
        cycle
      end if
      best_lambda(1:nv) = max(best_lambda(1:nv), 0.0_wp)      ! clamped onto the piece
      best_lambda(1:nv) = best_lambda(1:nv)/sum(best_lambda(1:nv))
      do q = 1, nv
        call append(list, todo(i), pieces%facets(q, best), best_lambda(q), k, .false.)
      end do
    end do
  end subroutine projections

  !> Append one triplet.
  subroutine append(list, slave, master, weight, tie, dual)
    type(triplets_t), intent(inout) :: list           !< the list
    integer, intent(in) :: slave, master, tie         !< mesh nodes, contact
    real(wp), intent(in) :: weight                    !< w
    logical, intent(in) :: dual                       !< dual mortar weight
    if (list%n == size(list%slave)) then
      list%slave = [list%slave, list%slave]
      list%master = [list%master, list%master]
      list%tie = [list%tie, list%tie]
      list%weight = [list%weight, list%weight]
      list%dual = [list%dual, list%dual]
    end if
    list%n = list%n + 1
    list%slave(list%n) = slave
    list%master(list%n) = master
    list%tie(list%n) = tie
    list%weight(list%n) = weight
    list%dual(list%n) = dual
  end subroutine append

  !> Normal distance of the point xp from piece p (a triangle; 2D: an edge) and the
  !> barycentric coordinates of its projection (triangle: lambda(1:3); edge: lambda(1:2)); a
  !> degenerate piece gives the distance huge.
  pure subroutine project(xp, x, pieces, p, dim, distance, lambda)
    real(wp), intent(in) :: xp(3)                     !< the point
    real(wp), intent(in) :: x(:,:)                    !< (3, mesh nodes) coordinates
    type(contact_surface_t), intent(in) :: pieces     !< triangles or edges
    integer, intent(in) :: p, dim                     !< piece, dimension
    real(wp), intent(out) :: distance                 !< |normal distance|
    real(wp), intent(out) :: lambda(3)                !< barycentric coordinates
    real(wp) :: e1(3), e2(3), normal(3), q(3), g11, g12, g22, det, t, d
    distance = huge(1.0_wp)
    lambda = 0.0_wp
    e1 = x(:, pieces%facets(2, p)) - x(:, pieces%facets(1, p))
    q = xp - x(:, pieces%facets(1, p))
    if (dim == 2) then
      g11 = dot_product(e1, e1)
      if (.not. g11 > 0.0_wp) return
      t = dot_product(q, e1)/g11
      lambda(1:2) = [1.0_wp - t, t]
      distance = norm2(q - t*e1)
      return
    end if
    e2 = x(:, pieces%facets(3, p)) - x(:, pieces%facets(1, p))
    normal = cross(e1, e2)
    if (.not. norm2(normal) > 0.0_wp) return
    normal = normal/norm2(normal)
    d = dot_product(q, normal)
    q = q - d*normal
    g11 = dot_product(e1, e1)
    g12 = dot_product(e1, e2)
    g22 = dot_product(e2, e2)
    det = g11*g22 - g12*g12
    lambda(2) = (dot_product(q, e1)*g22 - dot_product(q, e2)*g12)/det
    lambda(3) = (dot_product(q, e2)*g11 - dot_product(q, e1)*g12)/det
    lambda(1) = 1.0_wp - lambda(2) - lambda(3)
    distance = abs(d)
  end subroutine project

  !> "contact ID" or "tied contact number k (no id)" for messages.
  function who(model, k) result(s)
    type(model_t), intent(in) :: model                !< the model
    integer, intent(in) :: k                          !< index in model%ties
    character(len=:), allocatable :: s
    if (model%ties(k)%id /= 0) then
      s = 'contact '//itoa(model%ties(k)%id)
    else
      s = 'tied contact number '//itoa(k)//' (no id)'
    end if
  end function who

end module mefem_tied_contact
