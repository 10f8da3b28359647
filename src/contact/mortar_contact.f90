!> Mortar segment-to-segment contact with penalty regularisation and Coulomb friction
!> (formulation section 5; seed paper section 3.3) for *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE
!> (_MORTAR): SURFA = slave (non-mortar), SURFB = master (mortar).
!>
!> *CONTACT_AUTOMATIC_SINGLE_SURFACE (doc/theory.md 10.9): SURFA is both the slave and the
!> master surface, so every pair of solid facets that meet is computed twice, each facet
!> once as the slave (two half passes: such a pair counts with half the penalty, so it is as
!> stiff as one surface-to-surface pass, and unbiased). Facets whose side is not known
!> (shells of rigid tools) are masters only, and their pairs count fully. Pairs of facets
!> that share a node are not candidates, and a pair whose slave facet lies deeper behind the
!> master facet than PENMAX (default DEFAULT_PENMAX) times the master element's thickness
!> normal to the facet is no partner: the other side of a thin body, not a penetration.
!>
!> One call (mortar_contact_forces) with the current positions of the surface nodes, per
!> interface:
!>  1. candidate facet pairs from the bucket search (mefem_contact_surfaces), rebuilt when a
!>     surface node has moved more than half the search margin since the last build;
!>  2. mortar weights of each candidate (mefem_mortar_segmentation);
!>  3. averaged unit normals n_A of the slave nodes (area-weighted outward normals of the
!>     slave facets, each times the fraction of it that partners cover); the weights summed
!>     per slave node into
!>     A_A = sum_B n_AB and the weighted gap vector G_A = sum_C n_AC x_C - sum_B n_AB x_B;
!>     pairs with an outward master facet facing the same way as the slave are skipped (the
!>     far side of a master body);
!>  4. normal gap g_A = n_A . G_A / A_A (< 0: penetration), pressure p_A = eps_A <-g_A>;
!>     with IGNORE /= 0 (card C) p_A = eps_A <-g_A - o_A>: o_A >= 0 is the penetration of
!>     node A at the first evaluation (an initial penetration is kept, not pushed out), and
!>     it only shrinks, to the current penetration, as the bodies separate (0 once the node
!>     has no partner);
!>  5. slip from the change of the weights at fixed positions (objective: a rigid motion of
!>     the pair gives none): ds_A = (I - n_A n_A) (G_A - G_A^old) / A_A, G_A^old with the
!>     previous call's weights and today's positions; Coulomb return map on the tangential
!>     traction, mu = FD + (FS - FD) exp(-DC |ds|/dt), eps_T = eps_A;
!>  6. nodal forces: slave f_B += sum_A n_AB tau_A, master f_C -= sum_A n_AC tau_A with the
!>     contact traction tau_A = -p_A n_A + t_A.
!> Penalty: one value per interface (a node-wise penalty turns a uniform penetration into a
!> non-uniform pressure and fails the patch test): eps = SLSFAC SFSA SFSB <K/h>, the area mean
!> over the slave facets of the bulk modulus over the element size normal to the facet
!> (LS-DYNA's SOFT = 0 stiffness as a pressure per unit gap), limited so that the contact
!> spring never lowers the stable time step: eps <= mass_limit min_A(m_A/a_A) / dt^2 (a_A the
!> slave node's tributary area). Statics (implicit) scales it by a factor, without the limit.
!>
!> Parallel (documented choice, doc/theory.md 10.8): contact surfaces are small next to the
!> volume, so every rank holds all of them (replicated data). The driver gathers the current
!> positions of the contact nodes (owners fill, one sum over ranks). The candidate search is
!> the same on every rank (same data, same order). With distribute (the explicit analysis on
!> more than one rank) the work is divided: step 2, the mortar kernels, by candidates: rank r
!> computes the weights of the r-th of nranks contiguous, equal slices of the candidate list
!> (in its global order), and one allgatherv of compact records (candidate number, n_AB, n_AC,
!> master normal: PAIR_RECORD_LENGTH reals per pair with overlap) concatenates the slices in
!> rank order, which is the global candidate order: every rank then holds the same pair list
!> as one rank would. Steps 3-5 by slave nodes: each rank takes a contiguous slice of the
!> slave nodes balanced by their pair entries (node_slice), each node's sums running over the
!> pairs in the global order, and one allgatherv of node records (results and state,
!> NODE_RECORD_LENGTH reals per node) in node order. Step 6 (the force scatter, O(pairs)) runs
!> on every rank alike. An interface with fewer than MIN_CANDIDATES_PER_RANK candidates per
!> rank is not divided (every rank computes all of it, as one rank would: no collectives).
!> Contact forces are thus the same bits on every rank and for any number of ranks; each rank
!> applies them at its local nodes.
module mefem_mortar_contact
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: status_t, fatal
  use mefem_strings, only: itoa
  use mefem_model, only: model_t, contact_t, MAT_RIGID
  use mefem_contact_surfaces, only: contact_surface_t, contact_search_t, &
                                    contact_surface_triangulate, &
                                    contact_surface_pair_build, contact_facet_area_vector, &
                                    contact_search_build
  use mefem_mortar_segmentation, only: mortar_segment_pair_2d, mortar_triangle_pair_3d
  use mefem_material_update, only: material_elastic_moduli
  use mefem_model_resolve, only: element_measure
  use mefem_output_mesh, only: NODES_OF_TOPO
  use mefem_comm, only: comm_rank, comm_size, comm_allgatherv_real
  use mefem_restart_file, only: restart_file_t, restart_put_ints, restart_put_reals, &
                                restart_get_ints, restart_get_reals, restart_get_ints_alloc, &
                                restart_get_reals_alloc
  implicit none
  private

  public :: mortar_contact_setup, mortar_contact_forces, mortar_contact_slave_rows
  public :: mortar_contact_set_masses, mortar_contact_erode
  public :: mortar_contact_restart_put, mortar_contact_restart_get

  real(wp), parameter :: MIN_MASS_LIMIT = 0.1_wp   !< eps a dt^2 / m at most, whatever
                                                   !< TSSFAC (contact_mass_limit): the spring's
                                                   !< period stays above 20 dt
  real(wp), parameter :: SLSFAC = 0.1_wp           !< *CONTROL_CONTACT SLSFAC (default)
  real(wp), parameter :: MARGIN_FACTOR = 0.5_wp    !< search margin / mean facet size (the
                                                   !< smaller of the slave and master means)
  integer, parameter :: MAX_VERTICES = 4           !< facet vertices (quadrilateral)
  real(wp), parameter :: FACING_COSINE = 0.25_wp   !< cos of the largest angle (75.5 deg)
                                                   !< between a slave normal and the reversed
                                                   !< normal of a master partner
  real(wp), parameter :: DEFAULT_PENMAX = 0.4_wp   !< single surface: deepest penetration of a
                                                   !< partner / the master element's thickness
                                                   !< (LS-DYNA's default for solids)

  !> Reals per pair in the records the ranks exchange: candidate number, n_ab (3 x 3), n_ac
  !> (3 x MAX_VERTICES), master normal (3).
  integer, parameter :: PAIR_RECORD_LENGTH = 1 + 9 + 3*MAX_VERTICES + 3
  !> Reals per slave node in the records the ranks exchange: A_A, g_A, p_A, n_A (3), t_A (3),
  !> master normal (3), t_A in the node's frame (2), initial-penetration offset o_A.
  integer, parameter :: NODE_RECORD_LENGTH = 15
  integer, parameter :: PAIR_REALS = 9 + 3*MAX_VERTICES + 3   !< reals of a pair (restart)
  !> An interface's work is divided among the ranks only when it has at least this many
  !> candidate pairs per rank: below, the 4 collectives of a divided evaluation (tens of us,
  !> far more on an oversubscribed machine) cost more than the kernels they share (about 0.5 us
  !> per candidate), and every rank computes the whole interface (the same bits either way).
  !> The environment variable MEFEM_CONTACT_DIVIDE_MIN overrides it (0: always divide; the
  !> rank-independence tests use it to divide their small interfaces).
  integer, parameter :: MIN_CANDIDATES_PER_RANK = 2000

  !> A candidate pair with overlap: facets and mortar weights.
  type :: pair_t
    integer :: candidate = 0                       !< position in the candidate list
    integer :: slave = 0, master = 0
    real(wp) :: n_ab(3, 3) = 0.0_wp                !< (slave vertex a, slave vertex b)
    real(wp) :: n_ac(3, MAX_VERTICES) = 0.0_wp     !< (slave vertex a, master vertex c)
    real(wp) :: master_normal(3) = 0.0_wp          !< unit master facet normal, turned to face
                                                   !< the slave (against the slave normal)
  end type pair_t

  !> One contact interface (replicated on every rank).
  type, public :: contact_interface_t
    integer :: id = 0                              !< contact id (its number if none)
    type(contact_surface_t) :: slave, master       !< SURFA, SURFB
    type(contact_search_t) :: search               !< bucket grid, kept between calls
    integer, allocatable :: candidates(:,:)        !< (2, :) candidate (slave, master) facets
    integer :: ncandidate = 0
    real(wp) :: margin = 0.0_wp                    !< search margin (length)
    real(wp), allocatable :: slave_normal(:,:)     !< (3, slave facets) unit normals, this call
    real(wp), allocatable :: master_normal_f(:,:)  !< (3, master facets) unit normals
    real(wp), allocatable :: x_search(:,:)         !< (3, surface nodes) positions at the
                                                   !< last search
    integer, allocatable :: surface_nodes(:)       !< slave and master nodes (mesh numbers)
    logical :: searched = .false.
    integer, allocatable :: slave_index(:)         !< (mesh nodes) position in slave%nodes
    real(wp) :: eps_material = 0.0_wp              !< SLSFAC SFSA SFSB K / h (area mean)
    real(wp) :: mass_per_area = 0.0_wp             !< min over slave nodes of m_A / a_A
    real(wp), allocatable :: slave_area(:)         !< (ns) a_A, reference configuration
    real(wp) :: fs = 0.0_wp, fd = 0.0_wp, dc = 0.0_wp
    real(wp) :: birth = 0.0_wp, death = huge(1.0_wp) !< BT, DT: active for BT <= t <= DT
    logical :: single = .false.                    !< single surface: master = slave facets
    real(wp), allocatable :: pass_weight(:)        !< (ns) single surface: factor on the
                                                   !< penalty of a slave node (1/2 for pairs
                                                   !< computed both ways, 1 against shells)
    real(wp), allocatable :: depth_limit(:)        !< (master facets) single surface: deepest
                                                   !< penetration of a partner (length)
    logical :: eroded = .false.                    !< some facet is out (eroded or inside)
    logical :: eroding = .false.                   !< faces exposed by erosion join (surfaces
                                                   !< hold the faces inside, neighbour > 0)
    logical, allocatable :: slave_gone(:)          !< (slave facets) out: its element eroded,
                                                   !< or a face inside whose neighbour lives
    logical, allocatable :: master_gone(:)         !< (master facets) the same
    real(wp), allocatable :: slave_facet_area(:)   !< (slave facets) reference area (eroding)
    real(wp), allocatable :: slave_mass(:)         !< (ns) the masses of the penalty's cap
    ! per slave node, last call
    real(wp), allocatable :: normal(:,:)           !< (3, ns) n_A
    real(wp), allocatable :: normal_old(:,:)       !< (3, ns) n_A of the call before
    real(wp), allocatable :: master_normal(:,:)    !< (3, ns) mean master normal under A
    real(wp), allocatable :: master_normal_old(:,:) !< (3, ns) the same, the call before
    real(wp), allocatable :: area(:)               !< (ns) A_A
    real(wp), allocatable :: area_old(:)           !< (ns) A_A of the call before
    real(wp), allocatable :: gap_vector(:,:)       !< (3, ns) G_A
    real(wp), allocatable :: gap(:)                !< (ns) g_A (0 where A_A = 0)
    real(wp), allocatable :: pressure(:)           !< (ns) p_A
    real(wp), allocatable :: traction(:,:)         !< (3, ns) tangential traction t_A
    real(wp), allocatable :: traction_local(:,:)   !< (2, ns) t_A in the node's convected
                                                   !< tangent frame (kept between calls)
    integer, allocatable :: frame_node(:)          !< (ns) slave node fixing the frame's e1
    logical :: keep_initial = .false.              !< IGNORE /= 0: initial penetrations kept
    logical :: divided = .false.                   !< this evaluation's work is divided
    logical :: evaluated = .false.                 !< the first evaluation has been made
    real(wp), allocatable :: offset(:)             !< (ns) o_A, penetration not pushed out
    logical, allocatable :: held(:)                !< (ns) a tiebreak's contact: the node is
                                                   !< still tied (no contact force; set and
                                                   !< cleared by the tie, mefem_explicit_ties)
    ! pairs of the last and of the call before
    integer :: npair = 0, npair_old = 0
    type(pair_t), allocatable :: pairs(:), pairs_old(:)
    real(wp), allocatable :: records(:)            !< this rank's pairs packed (distributed)
    real(wp), allocatable :: all_records(:)        !< every rank's, in rank order
    real(wp), allocatable :: node_records(:)       !< this rank's slave-node results packed
    real(wp), allocatable :: all_node_records(:)   !< every rank's, in rank order
    real(wp), allocatable :: gap_old(:,:)          !< (3, ns) G_A with the old weights
    integer, allocatable :: node_work(:)           !< (ns) work per slave node (node_slice)
    ! resultants of the last call (rcforc)
    real(wp) :: force_slave(3) = 0.0_wp            !< sum of the slave nodal forces
    real(wp) :: force_master(3) = 0.0_wp           !< sum of the master nodal forces
    real(wp) :: normal_force = 0.0_wp              !< sum A_A p_A
    real(wp) :: tangential_force = 0.0_wp          !< |sum A_A t_A|
  end type contact_interface_t

  !> All interfaces and the contact nodes they use.
  type, public :: mortar_contact_t
    integer :: dim = 3
    integer :: n = 0                               !< interfaces
    logical :: distributed = .false.               !< mortar kernels divided among the ranks
    integer :: rank = 0, nranks = 1                !< this rank, ranks sharing the kernels
    integer :: divide_min = MIN_CANDIDATES_PER_RANK !< candidates per rank to divide
    real(wp) :: mass_limit = MIN_MASS_LIMIT        !< penalty cap eps a_A dt^2 / m_A at most
                                                   !< (contact_mass_limit)
    type(contact_interface_t), allocatable :: interfaces(:)
    integer :: nnode = 0                           !< contact nodes (union of all surfaces)
    integer, allocatable :: node_global(:)         !< (nnode) mesh nodes, ascending
    integer, allocatable :: node_index(:)          !< (mesh nodes) position in node_global
    real(wp), allocatable :: x(:,:)                !< (3, mesh nodes) current positions (only
                                                   !< the contact nodes are kept up to date)
    real(wp), allocatable :: force(:,:)            !< (3, nnode) contact force of the last call
    real(wp), allocatable :: pressure(:)           !< (nnode) slave contact pressure (output)
    real(wp), allocatable :: gap(:)                !< (nnode) slave normal gap (output)
  end type mortar_contact_t

contains

  !> Build every interface of the model: surfaces, contact nodes, penalty constants.
  !> mass(mesh nodes): lumped masses (the time-step limit of the penalty). distribute (default
  !> no): divide the mortar kernels among the ranks (every rank must then call
  !> mortar_contact_forces with the same positions, as the explicit analysis does).
  subroutine mortar_contact_setup(model, mass, contact, distribute)
    type(model_t), intent(in) :: model                !< resolved model
    real(wp), intent(in) :: mass(:)                   !< (mesh nodes) lumped masses
    type(mortar_contact_t), intent(out) :: contact    !< the contact data
    logical, intent(in), optional :: distribute       !< divide the kernels among the ranks
    type(status_t) :: status
    logical, allocatable :: used(:)
    integer :: k, i, ns, f
    contact%dim = model%dimension
    contact%mass_limit = contact_mass_limit(model%controls%tssfac)
    contact%distributed = .false.
    if (present(distribute)) contact%distributed = distribute
    if (contact%distributed) contact%distributed = comm_size() > 1
    if (contact%distributed) then
      contact%rank = comm_rank()
      contact%nranks = comm_size()
      contact%divide_min = divide_threshold()
    end if
    contact%n = model%n_contacts
    allocate(contact%interfaces(contact%n), used(model%nodes%n))
    used = .false.
    do k = 1, contact%n
      associate (c => model%contacts(k), it => contact%interfaces(k))
        it%id = merge(c%id, k, c%id > 0)
        call contact_surface_pair_build(model, k, it%slave, it%master, status)
        if (.not. status%ok) call fatal(status%message)
        it%single = c%single_surface
        if (it%single) call partner_depth_limits(model, c, it)
        ! the slave side integrates over triangles: quadrilateral faces (hexahedra,
        ! quadrilateral segments) are cut in two
        call contact_surface_triangulate(it%slave)
        ! eroding: the faces inside are out until erosion exposes them
        it%eroding = c%eroding
        allocate(it%slave_gone(it%slave%nfacet), it%master_gone(it%master%nfacet))
        it%slave_gone = it%slave%neighbour > 0
        it%master_gone = it%master%neighbour > 0
        it%eroded = any(it%slave_gone) .or. any(it%master_gone)
        used(it%slave%nodes) = .true.
        used(it%master%nodes) = .true.
        it%fs = c%fs
        it%fd = c%fd
        it%keep_initial = c%ignore /= 0
        it%dc = c%dc
        it%birth = c%birth
        it%death = c%death
        if (it%fd == 0.0_wp) it%fd = it%fs
        ns = size(it%slave%nodes)
        allocate(it%slave_index(model%nodes%n))
        it%slave_index = 0
        it%slave_index(it%slave%nodes) = [(i, i = 1, ns)]
        call slave_penalty(model, c, mass, it)
        allocate(it%normal(3, ns), it%area(ns), it%area_old(ns), it%gap_vector(3, ns), &
                 it%gap(ns), it%pressure(ns), it%traction(3, ns), it%pairs(0), it%pairs_old(0), &
                 it%traction_local(2, ns), it%frame_node(ns), it%normal_old(3, ns), &
                 it%master_normal(3, ns), it%master_normal_old(3, ns))
        it%normal = 0.0_wp
        it%master_normal = 0.0_wp
        it%traction = 0.0_wp
        it%traction_local = 0.0_wp
        ! the frame of node A: e1 towards another vertex of the first facet that has A
        it%frame_node = 0
        do f = it%slave%nfacet, 1, -1
          do i = 1, it%slave%nvertex(f)
            it%frame_node(it%slave%local(i, f)) = &
                it%slave%nodes(it%slave%local(mod(i, it%slave%nvertex(f)) + 1, f))
          end do
        end do
        it%pressure = 0.0_wp
        it%gap = 0.0_wp
        it%area = 0.0_wp
        it%area_old = 0.0_wp
        allocate(it%offset(ns))
        it%offset = 0.0_wp
        it%margin = MARGIN_FACTOR*min(mean_facet_size(it%master, model%nodes%x, &
                                                      it%master_gone), &
                                      mean_facet_size(it%slave, model%nodes%x, it%slave_gone))
        it%surface_nodes = [it%slave%nodes, it%master%nodes]
        allocate(it%x_search(3, size(it%surface_nodes)))
      end associate
    end do
    contact%node_global = pack([(i, i = 1, model%nodes%n)], used)
    contact%nnode = size(contact%node_global)
    allocate(contact%node_index(model%nodes%n))
    contact%node_index = 0
    contact%node_index(contact%node_global) = [(i, i = 1, contact%nnode)]
    allocate(contact%x(3, model%nodes%n), contact%force(3, contact%nnode), &
             contact%pressure(contact%nnode), contact%gap(contact%nnode))
    contact%x = model%nodes%x
    contact%force = 0.0_wp
    contact%pressure = 0.0_wp
    contact%gap = 0.0_wp
  end subroutine mortar_contact_setup

  !> The explicit penalty's cap eps a_A dt^2 / m_A (doc/theory.md 10.5): a quarter of the
  !> margin the step leaves, 1 - TSSFAC^2 (the cells' bound gives omega_c^2 dt^2 <= 4 TSSFAC^2,
  !> so the contact springs may add 4 (1 - TSSFAC^2); a quarter at the slave node leaves room
  !> for the master side and for neighbouring springs on shared master nodes), but at least
  !> MIN_MASS_LIMIT (TSSFAC above 0.95, where the bound's own distance from the true step is
  !> the margin).
  pure real(wp) function contact_mass_limit(tssfac)
    real(wp), intent(in) :: tssfac                    !< *CONTROL_TIMESTEP TSSFAC
    contact_mass_limit = max(MIN_MASS_LIMIT, 1.0_wp - tssfac**2)
  end function contact_mass_limit

  !> Candidates per rank from which an interface is divided: MIN_CANDIDATES_PER_RANK, or the
  !> value of the environment variable MEFEM_CONTACT_DIVIDE_MIN (an integer >= 0) if set.
  integer function divide_threshold()
    character(len=32) :: text
    integer :: length, env_status, value, read_status
    divide_threshold = MIN_CANDIDATES_PER_RANK
    call get_environment_variable('MEFEM_CONTACT_DIVIDE_MIN', text, length, env_status)
    if (env_status /= 0 .or. length == 0) return
    read(text, *, iostat=read_status) value
    if (read_status /= 0 .or. value < 0) call fatal('MEFEM_CONTACT_DIVIDE_MIN = '// &
        trim(text)//': expected an integer >= 0 (candidate pairs per rank)')
    divide_threshold = value
  end function divide_threshold

  !> Single surface: per master facet the deepest penetration a slave facet may have and
  !> still be its partner, PENMAX (DEFAULT_PENMAX when 0) times the thickness of the
  !> facet's element normal to the facet (the distance of its farthest node from the facet's
  !> plane, reference configuration). Facets without an element, or whose side is not known
  !> (shells), get no limit.
  subroutine partner_depth_limits(model, c, it)
    type(model_t), intent(in) :: model                !< resolved model
    type(contact_t), intent(in) :: c                  !< the contact card
    type(contact_interface_t), intent(inout) :: it    !< the interface (master built)
    real(wp) :: a(3), normal(3), thickness, fraction
    integer :: f, e, i, nv, origin
    fraction = DEFAULT_PENMAX
    if (c%penmax > 0.0_wp) fraction = c%penmax
    allocate(it%depth_limit(it%master%nfacet))
    it%depth_limit = huge(1.0_wp)
    do f = 1, it%master%nfacet
      e = it%master%element(f)
      if (e <= 0 .or. .not. it%master%outward(f)) cycle
      a = contact_facet_area_vector(it%master, f, model%nodes%x)
      if (norm2(a) <= 0.0_wp) cycle
      normal = a/norm2(a)
      origin = it%master%facets(1, f)
      nv = NODES_OF_TOPO(model%elements%topology(e))
      thickness = 0.0_wp
      do i = 1, nv
        thickness = max(thickness, -dot_product(normal, model%nodes%x(:, &
            model%elements%conn(i, e)) - model%nodes%x(:, origin)))
      end do
      if (thickness > 0.0_wp) it%depth_limit(f) = fraction*thickness
    end do
  end subroutine partner_depth_limits

  !> Single surface: drop the candidates whose slave and master facets share a node (a facet
  !> and its neighbours), keeping the order of the others.
  subroutine drop_neighbours(it)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    integer :: k, kept, s, m, i
    logical :: shared
    kept = 0
    do k = 1, it%ncandidate
      s = it%candidates(1, k)
      m = it%candidates(2, k)
      shared = .false.
      do i = 1, it%slave%nvertex(s)
        shared = shared .or. any(it%master%facets(1:it%master%nvertex(m), m) == &
                                 it%slave%facets(i, s))
      end do
      if (shared) cycle
      kept = kept + 1
      it%candidates(:, kept) = it%candidates(:, k)
    end do
    it%ncandidate = kept
  end subroutine drop_neighbours

  !> The facets of eroded elements leave the interfaces, and in eroding contacts the faces
  !> inside whose neighbour has eroded join them (the next search, forced now, sees the
  !> change; the penalty's cap is taken again over the slave nodes that have facets).
  !> live(e): the cells of element e not eroded (mesh elements; every rank alike).
  subroutine mortar_contact_erode(contact, live)
    type(mortar_contact_t), intent(inout) :: contact  !< contact data
    integer, intent(in) :: live(:)                    !< (mesh elements) live cells
    integer :: k
    do k = 1, contact%n
      associate (it => contact%interfaces(k))
        it%slave_gone = gone(it%slave)
        it%master_gone = gone(it%master)
        it%eroded = any(it%slave_gone) .or. any(it%master_gone)
        if (it%eroded) it%searched = .false.
        if (it%eroding) call active_slave_areas(it)
      end associate
    end do
  contains
    !> Per facet: its element (a solid's; shells and faces without one never erode) eroded,
    !> or a face inside whose neighbour has not.
    function gone(surface)
      type(contact_surface_t), intent(in) :: surface
      logical :: gone(surface%nfacet)
      integer :: f
      do f = 1, surface%nfacet
        gone(f) = .false.
        if (surface%element(f) > 0) gone(f) = live(surface%element(f)) == 0
        if (surface%neighbour(f) > 0) gone(f) = gone(f) .or. live(surface%neighbour(f)) > 0
      end do
    end function gone
  end subroutine mortar_contact_erode

  !> Eroding contact: the slave nodes' reference areas a_A from the facets in the contact
  !> (slave_facet_area) and the penalty's cap min m_A / a_A again.
  pure subroutine active_slave_areas(it)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    integer :: f, i
    it%slave_area = 0.0_wp
    do f = 1, it%slave%nfacet
      if (it%slave_gone(f)) cycle
      do i = 1, it%slave%nvertex(f)
        it%slave_area(it%slave%local(i, f)) = it%slave_area(it%slave%local(i, f)) + &
            it%slave%weight(f)*it%slave_facet_area(f)/real(it%slave%nvertex(f), wp)
      end do
    end do
    call set_mass_per_area(it, it%slave_mass)
  end subroutine active_slave_areas

  !> Drop the candidate pairs with a facet of an eroded element.
  subroutine drop_eroded(it)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    integer :: k, kept
    kept = 0
    do k = 1, it%ncandidate
      if (it%slave_gone(it%candidates(1, k)) .or. it%master_gone(it%candidates(2, k))) cycle
      kept = kept + 1
      it%candidates(:, kept) = it%candidates(:, k)
    end do
    it%ncandidate = kept
  end subroutine drop_eroded

  !> Single surface: the penalty factor of the slave nodes first:last, the mean over the
  !> node's pairs (weighted by their share sum_B n_AB of A_A) of 1/2 for a pair with a solid
  !> master facet (computed again the other way round) and 1 for a shell master (one way).
  subroutine pass_weights(it, first, last)
    type(contact_interface_t), intent(inout) :: it    !< the interface (area set)
    integer, intent(in) :: first, last                !< slave nodes wanted
    integer :: k, a, slot
    real(wp) :: w
    if (.not. allocated(it%pass_weight)) allocate(it%pass_weight(size(it%slave%nodes)))
    it%pass_weight = 0.0_wp
    do k = 1, it%npair
      associate (p => it%pairs(k))
        w = merge(0.5_wp, 1.0_wp, it%master%outward(p%master))
        do a = 1, it%slave%nvertex(p%slave)
          slot = it%slave%local(a, p%slave)
          if (slot < first .or. slot > last) cycle
          it%pass_weight(slot) = it%pass_weight(slot) + w*sum(p%n_ab(a, :))
        end do
      end associate
    end do
    do slot = first, last
      if (it%area(slot) > 0.0_wp) it%pass_weight(slot) = it%pass_weight(slot)/it%area(slot)
    end do
  end subroutine pass_weights

  !> Single surface: the slave facet s lies deeper behind the master facet m (outward unit
  !> normal n_m) than the facet's depth limit, measured from centroid to centroid along n_m.
  logical function too_deep(contact, it, s, m, n_m)
    type(mortar_contact_t), intent(in) :: contact     !< contact data (positions)
    type(contact_interface_t), intent(in) :: it       !< the interface
    integer, intent(in) :: s, m                       !< slave and master facets
    real(wp), intent(in) :: n_m(3)                    !< master facet unit normal
    real(wp) :: cs(3), cm(3)
    integer :: i
    too_deep = .false.
    if (it%depth_limit(m) >= huge(1.0_wp)) return
    cs = 0.0_wp
    do i = 1, it%slave%nvertex(s)
      cs = cs + contact%x(:, it%slave%facets(i, s))
    end do
    cm = 0.0_wp
    do i = 1, it%master%nvertex(m)
      cm = cm + contact%x(:, it%master%facets(i, m))
    end do
    cs = cs/real(it%slave%nvertex(s), wp)
    cm = cm/real(it%master%nvertex(m), wp)
    too_deep = dot_product(cs - cm, n_m) < -it%depth_limit(m)
  end function too_deep

  !> The penalty constants of an interface, one value for the whole interface (a penalty
  !> that varied from node to node would turn a uniform penetration into a non-uniform
  !> pressure and fail the contact patch test):
  !>   eps_material = SLSFAC SFSA SFSB <K / h>, the area-weighted mean over the slave facets
  !>     of the bulk modulus over the element's size normal to the facet (volume / facet area
  !>     in 3D, area / edge length in 2D, reference configuration): LS-DYNA's SOFT = 0
  !>     stiffness k = SLSFAC SFS K A^2 / V as a pressure per unit gap;
  !>   mass_per_area = min over slave nodes of m_A / a_A (a_A = int N_A over the slave
  !>     facets), for the time-step limit eps <= mass_limit mass_per_area / dt^2.
  subroutine slave_penalty(model, c, mass, it)
    type(model_t), intent(in) :: model                !< resolved model
    type(contact_t), intent(in) :: c                  !< the contact card
    real(wp), intent(in) :: mass(:)                   !< (mesh nodes) lumped masses
    type(contact_interface_t), intent(inout) :: it    !< the interface
    real(wp) :: lambda, mu, bulk, size_normal, measure, a(3), total_area, weighted
    real(wp) :: corners(3, 8)
    real(wp), allocatable :: node_area(:)
    integer :: f, e, i, m, nv
    allocate(node_area(size(it%slave%nodes)))
    node_area = 0.0_wp
    total_area = 0.0_wp
    weighted = 0.0_wp
    allocate(it%slave_facet_area(it%slave%nfacet))
    do f = 1, it%slave%nfacet
      a = contact_facet_area_vector(it%slave, f, model%nodes%x)
      it%slave_facet_area(f) = norm2(a)
      if (it%slave_gone(f)) cycle                     ! (eroding: a face inside)
      do i = 1, it%slave%nvertex(f)
        node_area(it%slave%local(i, f)) = node_area(it%slave%local(i, f)) + &
            it%slave%weight(f)*norm2(a)/real(it%slave%nvertex(f), wp)
      end do
    end do
    it%slave_area = node_area
    call set_mass_per_area(it, mass(it%slave%nodes))
    do f = 1, it%slave%nfacet
      e = it%slave%element(f)
      if (e <= 0 .or. it%slave_gone(f)) cycle
      m = model%parts(model%elements%part(e))%material
      if (m <= 0) cycle
      ! deformable elements only: a rigid tool's modulus says nothing about the body it
      ! presses (single surfaces of all parts hold both)
      if (model%materials(m)%kind == MAT_RIGID) cycle
      call material_elastic_moduli(model%materials(m), lambda, mu)
      bulk = lambda + 2.0_wp*mu/3.0_wp
      nv = NODES_OF_TOPO(model%elements%topology(e))
      do i = 1, nv
        corners(:, i) = model%nodes%x(:, model%elements%conn(i, e))
      end do
      measure = abs(element_measure(model%elements%topology(e), corners(:, 1:nv)))
      a = contact_facet_area_vector(it%slave, f, model%nodes%x)
      if (norm2(a) <= 0.0_wp) cycle
      size_normal = measure/(norm2(a)*it%slave%pieces(f))   ! (the whole face's area)
      total_area = total_area + it%slave%weight(f)*norm2(a)
      weighted = weighted + it%slave%weight(f)*norm2(a)*bulk/size_normal
    end do
    it%eps_material = 0.0_wp
    if (total_area > 0.0_wp) it%eps_material = SLSFAC*c%sfsa*c%sfsb*weighted/total_area
    if (.not. (it%eps_material > 0.0_wp)) call fatal('contact '//itoa(it%id)//': SURFA '// &
        'has no deformable elements to take the penalty stiffness from (SURFA must be the '// &
        'deformable side; rigid tools belong on SURFB)')
  end subroutine slave_penalty

  !> Mean size of a surface's facets that are not out: length (2D) or square root of the
  !> area (3D).
  real(wp) function mean_facet_size(surface, x, out)
    type(contact_surface_t), intent(in) :: surface    !< the surface
    real(wp), intent(in) :: x(:,:)                    !< (3, mesh nodes) coordinates
    logical, intent(in) :: out(:)                     !< (facets) facets left out
    real(wp) :: total
    integer :: f
    total = 0.0_wp
    do f = 1, surface%nfacet
      if (out(f)) cycle
      if (surface%dim == 2) then
        total = total + norm2(contact_facet_area_vector(surface, f, x))
      else
        total = total + sqrt(norm2(contact_facet_area_vector(surface, f, x)))
      end if
    end do
    mean_facet_size = total/real(max(1, count(.not. out(1:surface%nfacet))), wp)
  end function mean_facet_size

  !> An interface outside its BT..DT window: no forces, no pressure, and its resultants (for
  !> rcforc) zero; its pairs and friction state are kept as they are.
  subroutine interface_at_rest(it)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    it%force_slave = 0.0_wp
    it%force_master = 0.0_wp
    it%normal_force = 0.0_wp
    it%tangential_force = 0.0_wp
    if (allocated(it%pressure)) it%pressure = 0.0_wp   ! (the implicit tangent reads them)
    if (allocated(it%traction)) it%traction = 0.0_wp
  end subroutine interface_at_rest

  !> m_A / a_A at its smallest over the interface's slave nodes (massless or arealess nodes
  !> left out), from the slave nodes' masses in slave%nodes order.
  pure subroutine set_mass_per_area(it, slave_mass)
    type(contact_interface_t), intent(inout) :: it    !< the interface (slave_area set)
    real(wp), intent(in) :: slave_mass(:)             !< (ns) masses of the slave nodes
    integer :: i
    it%slave_mass = slave_mass                        ! (kept: active_slave_areas)
    it%mass_per_area = huge(1.0_wp)
    do i = 1, size(slave_mass)
      if (it%slave_area(i) > 0.0_wp .and. slave_mass(i) > 0.0_wp) &
        it%mass_per_area = min(it%mass_per_area, slave_mass(i)/it%slave_area(i))
    end do
  end subroutine set_mass_per_area

  !> New nodal masses of the contact nodes (contact%node_global order) for the penalty's
  !> time-step limit: with mass scaling the integrator's masses grow where the step needs it,
  !> and the limit eps <= mass_limit m_A / (a_A dt^2) must use those masses with the scaled
  !> step (the physical masses with it would make the contact soft by the added mass' ratio).
  subroutine mortar_contact_set_masses(contact, node_mass)
    type(mortar_contact_t), intent(inout) :: contact  !< contact data
    real(wp), intent(in) :: node_mass(:)              !< (nnode) masses of the contact nodes
    integer :: k
    do k = 1, contact%n
      associate (it => contact%interfaces(k))
        call set_mass_per_area(it, node_mass(contact%node_index(it%slave%nodes)))
      end associate
    end do
  end subroutine mortar_contact_set_masses

  !> Contact forces of every interface at the positions contact%x (the contact nodes' rows
  !> current), for a step dt (penalty limit); into contact%force (contact-node numbering).
  subroutine mortar_contact_forces(contact, dt, penalty_scale, time)
    type(mortar_contact_t), intent(inout) :: contact  !< contact data, positions current
    real(wp), intent(in) :: dt                        !< the time step just taken (0: no
                                                      !< time-step limit, statics)
    real(wp), intent(in), optional :: penalty_scale   !< factor on eps_material (default 1)
    real(wp), intent(in), optional :: time            !< time of the positions: an interface
                                                      !< acts for BT <= time <= DT only
    integer :: k
    contact%force = 0.0_wp
    contact%pressure = 0.0_wp
    contact%gap = 0.0_wp
    do k = 1, contact%n
      if (present(time)) then
        if (time < contact%interfaces(k)%birth .or. time > contact%interfaces(k)%death) then
          call interface_at_rest(contact%interfaces(k))
          cycle
        end if
      end if
      if (present(penalty_scale)) then
        call interface_forces(contact, contact%interfaces(k), dt, penalty_scale)
      else
        call interface_forces(contact, contact%interfaces(k), dt, 1.0_wp)
      end if
    end do
  end subroutine mortar_contact_forces

  !> For the frozen-geometry tangent of the implicit analysis (formulation 5.5): per slave
  !> node a of interface k (position in slave%nodes) the slave mesh nodes B with
  !> w_aB = sum over the pairs of n_AB, in CSR form (start(a):start(a+1)-1 of nodes/weights),
  !> from the last call of mortar_contact_forces. The penalty tangent of an active node is
  !> then eps/A_A w_aB w_aB' (n_A n_A^T), eps = p_A / (-g_A).
  subroutine mortar_contact_slave_rows(contact, k, start, nodes, weights)
    type(mortar_contact_t), intent(in) :: contact     !< contact data after a force call
    integer, intent(in) :: k                          !< interface
    integer, allocatable, intent(out) :: start(:)     !< (slave nodes + 1) row starts
    integer, allocatable, intent(out) :: nodes(:)     !< mesh nodes B
    real(wp), allocatable, intent(out) :: weights(:)  !< w_aB
    integer, allocatable :: fill(:), marker(:)
    integer :: ns, q, i, j, a, b, na, length, out
    associate (it => contact%interfaces(k))
      ns = size(it%slave%nodes)
      allocate(start(ns + 1), fill(ns), marker(ns))
      ! bound on the entries of each row (duplicates included), then fill
      fill = 0
      do q = 1, it%npair
        na = it%slave%nvertex(it%pairs(q)%slave)
        do i = 1, na
          a = it%slave%local(i, it%pairs(q)%slave)
          fill(a) = fill(a) + na
        end do
      end do
      start(1) = 1
      do a = 1, ns
        start(a + 1) = start(a) + fill(a)
      end do
      allocate(nodes(start(ns + 1) - 1), weights(start(ns + 1) - 1))
      fill = 0
      do q = 1, it%npair
        associate (p => it%pairs(q))
          na = it%slave%nvertex(p%slave)
          do i = 1, na
            a = it%slave%local(i, p%slave)
            do j = 1, na
              nodes(start(a) + fill(a)) = it%slave%facets(j, p%slave)
              weights(start(a) + fill(a)) = p%n_ab(i, j)
              fill(a) = fill(a) + 1
            end do
          end do
        end associate
      end do
      ! merge repeated B within each row, in place
      marker = 0
      out = 0
      do a = 1, ns
        length = fill(a)
        i = start(a)
        start(a) = out + 1
        do j = i, i + length - 1
          b = it%slave_index(nodes(j))
          if (marker(b) >= start(a)) then
            weights(marker(b)) = weights(marker(b)) + weights(j)
          else
            out = out + 1
            nodes(out) = nodes(j)
            weights(out) = weights(j)
            marker(b) = out
          end if
        end do
      end do
      start(ns + 1) = out + 1
    end associate
  end subroutine mortar_contact_slave_rows

  !> One interface: steps 1-6 of the module header. Distributed, steps 3-5 run for this
  !> rank's slice of the slave nodes (node_slice: contiguous, balanced by the pairs of the
  !> nodes) and the per-node results and state are exchanged (exchange_nodes) before the
  !> nodal forces; each node's sums run over the pairs in the same order as on one rank.
  subroutine interface_forces(contact, it, dt, penalty_scale)
    type(mortar_contact_t), intent(inout) :: contact  !< contact data
    type(contact_interface_t), intent(inout) :: it    !< the interface
    real(wp), intent(in) :: dt                        !< the time step just taken
    real(wp), intent(in) :: penalty_scale             !< factor on eps_material
    real(wp) :: eps, slip(3), trial(3), old(3), magnitude, mu, limit, tau(3), e1(3), e2(3)
    real(wp) :: penetration
    integer :: a, dim, ns, first, last
    dim = contact%dim
    ns = size(it%slave%nodes)
    first = 1
    last = ns
    if (.not. allocated(it%gap_old)) allocate(it%gap_old(3, ns))
    call update_candidates(contact, it)
    ! the same decision on every rank (the candidate list is the same everywhere)
    it%divided = contact%distributed .and. &
                 int(it%ncandidate, i8) >= int(contact%divide_min, i8)*contact%nranks
    ! today's weights; the previous call's (with today's positions: slip, only with
    ! friction) for this rank's slave nodes
    call swap_pairs(it)
    it%npair_old = it%npair
    it%area_old = it%area
    it%normal_old = it%normal
    it%master_normal_old = it%master_normal
    call mortar_pairs(contact, it)
    if (it%divided) call node_slice(contact, it, first, last)
    if (it%fs > 0.0_wp) call weighted_sums(contact%x, it, it%pairs_old, it%npair_old, first, &
                                           last, it%gap_old)
    call slave_normals(contact, it, first, last)
    call weighted_sums(contact%x, it, it%pairs, it%npair, first, last, it%gap_vector, it%area)
    if (it%single) call pass_weights(it, first, last)
    ! gap, pressure, friction per slave node
    do a = first, last
      if (it%area(a) <= 0.0_wp) then
        it%gap(a) = 0.0_wp
        it%pressure(a) = 0.0_wp
        it%traction(:, a) = 0.0_wp
        it%offset(a) = 0.0_wp
        cycle
      end if
      it%gap(a) = dot_product(it%normal(:, a), it%gap_vector(:, a))/it%area(a)
      if (allocated(it%held)) then
        if (it%held(a)) then                          ! its tie holds it
          it%pressure(a) = 0.0_wp
          it%traction(:, a) = 0.0_wp
          it%traction_local(:, a) = 0.0_wp
          it%offset(a) = 0.0_wp
          cycle
        end if
      end if
      eps = penalty_scale*it%eps_material
      if (dt > 0.0_wp) eps = min(eps, contact%mass_limit*it%mass_per_area/(dt*dt))
      if (it%single) eps = it%pass_weight(a)*eps
      penetration = max(-it%gap(a), 0.0_wp)
      if (it%keep_initial) then
        ! the initial penetration is remembered; separating reduces it for good
        if (it%evaluated) then
          it%offset(a) = min(it%offset(a), penetration)
        else
          it%offset(a) = penetration
        end if
        penetration = max(penetration - it%offset(a), 0.0_wp)
      end if
      it%pressure(a) = eps*penetration
      if (it%pressure(a) <= 0.0_wp .or. it%fs <= 0.0_wp .or. it%area_old(a) <= 0.0_wp) then
        it%traction(:, a) = 0.0_wp
        it%traction_local(:, a) = 0.0_wp
        cycle
      end if
      ! slip from the change of the weights at fixed positions, less the part a relative
      ! rotation of the two surfaces produces at the penetrated gap g (the weights follow
      ! the slave normal: turning it by dn relative to the master moves the projected master
      ! point by g dn, which is no slip; a rigid rotation of the pair turns n and the master
      ! normal m (~ -n) together, dn + dm = 0, and keeps this term zero)
      slip = tangential(it%normal(:, a), (it%gap_vector(:, a) - it%gap_old(:, a))/it%area(a) - &
          it%gap(a)*((it%normal(:, a) - it%normal_old(:, a)) + &
                     (it%master_normal(:, a) - it%master_normal_old(:, a))))
      ! the old traction from its components in the node's convected frame (it turns with
      ! the surface: objective under rigid rotations, in-plane spin included)
      call tangent_frame(contact, it, a, e1, e2)
      old = it%traction_local(1, a)*e1 + it%traction_local(2, a)*e2
      ! tangential penalty: SLSFAC SFSA SFSB K/h in both analyses (the normal one of statics
      ! is penalty_scale times stiffer; a stick spring as stiff makes Newton's stick/slip
      ! states cycle, doc/theory.md section 10)
      trial = old - (eps/penalty_scale)*slip
      mu = it%fd + (it%fs - it%fd)*exp(-it%dc*norm2(slip)/max(dt, tiny(1.0_wp)))
      limit = mu*it%pressure(a)
      magnitude = norm2(trial)
      if (magnitude > limit) trial = trial*(limit/magnitude)
      it%traction(:, a) = trial
      it%traction_local(:, a) = [dot_product(trial, e1), dot_product(trial, e2)]
    end do
    if (it%divided) call exchange_nodes(it, first, last)
    it%evaluated = .true.
    it%normal_force = 0.0_wp
    do a = 1, ns
      if (it%area(a) > 0.0_wp) it%normal_force = it%normal_force + it%area(a)*it%pressure(a)
    end do
    ! nodal forces
    call nodal_forces(contact, it)
    it%tangential_force = 0.0_wp
    tau = 0.0_wp
    do a = 1, ns
      tau = tau + it%area(a)*it%traction(:, a)
      associate (cn => contact%node_index(it%slave%nodes(a)))
        if (it%area(a) > 0.0_wp) then
          contact%pressure(cn) = max(contact%pressure(cn), it%pressure(a))
          contact%gap(cn) = it%gap(a)
        end if
      end associate
    end do
    it%tangential_force = norm2(tau(1:dim))
  end subroutine interface_forces

  !> This rank's slice first:last of the slave nodes for steps 3-5: the ranks take
  !> contiguous slices in rank order, balanced by the work of a node (1 + its pair-vertex
  !> entries, counted from the pair list every rank holds, so every rank finds the same
  !> slices). Empty slice: first = 1, last = 0.
  subroutine node_slice(contact, it, first, last)
    type(mortar_contact_t), intent(in) :: contact     !< contact data (rank, ranks)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    integer, intent(out) :: first, last               !< this rank's slave nodes
    integer(i8) :: total, lower, upper, running
    integer :: k, i, a, ns
    ns = size(it%slave%nodes)
    if (.not. allocated(it%node_work)) allocate(it%node_work(ns))
    it%node_work = 1
    do k = 1, it%npair
      do i = 1, it%slave%nvertex(it%pairs(k)%slave)
        a = it%slave%local(i, it%pairs(k)%slave)
        it%node_work(a) = it%node_work(a) + 1
      end do
    end do
    total = sum(int(it%node_work, i8))
    lower = total*contact%rank/contact%nranks
    upper = total*(contact%rank + 1)/contact%nranks
    first = 1
    last = 0
    running = 0
    do a = 1, ns
      running = running + it%node_work(a)
      if (running <= lower) then
        first = a + 1
      else if (running <= upper) then
        last = a
      else
        exit
      end if
    end do
    if (last < first) then
      first = 1
      last = 0
    end if
  end subroutine node_slice

  !> Every rank's slave-node results and state on every rank: A_A, g_A, p_A, n_A, t_A, the
  !> master normal under A, t_A in the node's frame and o_A, of this rank's slice first:last,
  !> packed as NODE_RECORD_LENGTH reals per node; the slices of all ranks concatenated in
  !> rank order (one allgatherv), which is the slave-node order.
  subroutine exchange_nodes(it, first, last)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    integer, intent(in) :: first, last                !< this rank's slave nodes
    integer :: a, o, n_values
    if (.not. allocated(it%node_records)) &
      allocate(it%node_records(NODE_RECORD_LENGTH*size(it%slave%nodes)))
    do a = first, last
      o = (a - first)*NODE_RECORD_LENGTH
      it%node_records(o + 1) = it%area(a)
      it%node_records(o + 2) = it%gap(a)
      it%node_records(o + 3) = it%pressure(a)
      it%node_records(o + 4:o + 6) = it%normal(:, a)
      it%node_records(o + 7:o + 9) = it%traction(:, a)
      it%node_records(o + 10:o + 12) = it%master_normal(:, a)
      it%node_records(o + 13:o + 14) = it%traction_local(:, a)
      it%node_records(o + 15) = it%offset(a)
    end do
    call comm_allgatherv_real(it%node_records, NODE_RECORD_LENGTH*max(0, last - first + 1), &
                              it%all_node_records, n_values)
    do a = 1, n_values/NODE_RECORD_LENGTH
      o = (a - 1)*NODE_RECORD_LENGTH
      it%area(a) = it%all_node_records(o + 1)
      it%gap(a) = it%all_node_records(o + 2)
      it%pressure(a) = it%all_node_records(o + 3)
      it%normal(:, a) = it%all_node_records(o + 4:o + 6)
      it%traction(:, a) = it%all_node_records(o + 7:o + 9)
      it%master_normal(:, a) = it%all_node_records(o + 10:o + 12)
      it%traction_local(:, a) = it%all_node_records(o + 13:o + 14)
      it%offset(a) = it%all_node_records(o + 15)
    end do
  end subroutine exchange_nodes

  !> The pairs of the last call become the old ones (buffers swapped, not reallocated).
  subroutine swap_pairs(it)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    type(pair_t), allocatable :: scratch(:)
    call move_alloc(it%pairs_old, scratch)
    call move_alloc(it%pairs, it%pairs_old)
    call move_alloc(scratch, it%pairs)
  end subroutine swap_pairs

  !> Convected tangent frame of slave node a: e1 along the tangential part of the edge to
  !> its frame node (3D) or along the surface (2D: n turned by 90 degrees), e2 = n x e1.
  subroutine tangent_frame(contact, it, a, e1, e2)
    type(mortar_contact_t), intent(in) :: contact     !< contact data (positions)
    type(contact_interface_t), intent(in) :: it       !< the interface
    integer, intent(in) :: a                          !< slave node (position in slave%nodes)
    real(wp), intent(out) :: e1(3), e2(3)             !< unit tangents
    real(wp) :: n(3), length
    n = it%normal(:, a)
    if (contact%dim == 2) then
      e1 = [-n(2), n(1), 0.0_wp]
      e2 = 0.0_wp
      return
    end if
    e1 = tangential(n, contact%x(:, it%frame_node(a)) - contact%x(:, it%slave%nodes(a)))
    length = norm2(e1)
    if (length > 0.0_wp) e1 = e1/length
    e2 = [n(2)*e1(3) - n(3)*e1(2), n(3)*e1(1) - n(1)*e1(3), n(1)*e1(2) - n(2)*e1(1)]
  end subroutine tangent_frame

  !> Tangential part (I - n n) v of v.
  pure function tangential(n, v) result(t)
    real(wp), intent(in) :: n(3), v(3)     !< unit normal, vector
    real(wp) :: t(3)
    t = v - dot_product(n, v)*n
  end function tangential

  !> Averaged unit normals of the slave nodes first:last: area-weighted outward normals of
  !> the slave facets, each weighted by the fraction of it that master partners cover in this
  !> call (sum of its pairs' n_AB over its length/area, at most 1), so that a node on the edge
  !> of the contact zone is not tilted by the free side faces of its body, and its normal
  !> turns continuously as a neighbour facet slides onto or off the master.
  subroutine slave_normals(contact, it, first, last)
    type(mortar_contact_t), intent(in) :: contact     !< contact data
    type(contact_interface_t), intent(inout) :: it    !< the interface
    integer, intent(in) :: first, last                !< slave nodes wanted (others: 0)
    real(wp) :: a(3), length
    integer :: f, i, k, slot
    real(wp) :: covered(it%slave%nfacet)
    covered = 0.0_wp
    do k = 1, it%npair
      covered(it%pairs(k)%slave) = covered(it%pairs(k)%slave) + sum(it%pairs(k)%n_ab)
    end do
    it%normal = 0.0_wp
    do f = 1, it%slave%nfacet
      if (covered(f) <= 0.0_wp) cycle
      if (all(it%slave%local(1:it%slave%nvertex(f), f) < first) .or. &
          all(it%slave%local(1:it%slave%nvertex(f), f) > last)) cycle
      a = contact_facet_area_vector(it%slave, f, contact%x)
      length = norm2(a)
      if (length <= 0.0_wp) cycle
      a = a*it%slave%weight(f)*min(1.0_wp, covered(f)/(it%slave%weight(f)*length))
      do i = 1, it%slave%nvertex(f)
        slot = it%slave%local(i, f)
        if (slot >= first .and. slot <= last) it%normal(:, slot) = it%normal(:, slot) + a
      end do
    end do
    do i = first, last
      length = norm2(it%normal(:, i))
      if (length > 0.0_wp) it%normal(:, i) = it%normal(:, i)/length
    end do
    ! the master normal under each slave node: weighted by its overlap integrals
    it%master_normal = 0.0_wp
    do k = 1, it%npair
      associate (p => it%pairs(k))
        do i = 1, it%slave%nvertex(p%slave)
          slot = it%slave%local(i, p%slave)
          if (slot < first .or. slot > last) cycle
          it%master_normal(:, slot) = it%master_normal(:, slot) + &
                                      sum(p%n_ac(i, :))*p%master_normal
        end do
      end associate
    end do
    do i = first, last
      length = norm2(it%master_normal(:, i))
      if (length > 0.0_wp) it%master_normal(:, i) = it%master_normal(:, i)/length
    end do
  end subroutine slave_normals

  !> Candidate pairs: rebuilt when a surface node moved more than half the margin since the
  !> last search (the pairs missed in between are then those that came closer than the
  !> margin, which cannot happen).
  subroutine update_candidates(contact, it)
    type(mortar_contact_t), intent(in) :: contact     !< contact data
    type(contact_interface_t), intent(inout) :: it    !< the interface
    real(wp) :: moved
    integer :: i
    moved = huge(1.0_wp)
    if (it%searched) then
      moved = 0.0_wp
      do i = 1, size(it%surface_nodes)
        moved = max(moved, norm2(contact%x(:, it%surface_nodes(i)) - it%x_search(:, i)))
      end do
    end if
    if (moved <= 0.5_wp*it%margin) return
    call contact_search_build(it%search, it%slave, it%master, contact%x, it%margin, &
                              it%candidates, it%ncandidate, it%slave_gone, it%master_gone)
    if (it%single) call drop_neighbours(it)
    if (it%eroded) call drop_eroded(it)
    it%x_search = contact%x(:, it%surface_nodes)
    it%searched = .true.
  end subroutine update_candidates

  !> Unit normals of the facets first:last of a surface at positions x (zero for a
  !> degenerate facet).
  subroutine facet_unit_normals(surface, x, first, last, normals)
    type(contact_surface_t), intent(in) :: surface    !< the surface
    real(wp), intent(in) :: x(:,:)                    !< (3, mesh nodes) positions
    integer, intent(in) :: first, last                !< facets wanted
    real(wp), allocatable, intent(inout) :: normals(:,:) !< (3, facets) reused between calls
    real(wp) :: a(3), length
    integer :: f
    if (.not. allocated(normals)) allocate(normals(3, surface%nfacet))
    do f = first, last
      a = contact_facet_area_vector(surface, f, x)
      length = norm2(a)
      normals(:, f) = 0.0_wp
      if (length > 0.0_wp) normals(:, f) = a/length
    end do
  end subroutine facet_unit_normals

  !> Mortar weights of every candidate pair with an overlap (into it%pairs, in candidate
  !> order). Distributed: this rank computes its slice of the candidates, and the slices of
  !> all ranks are exchanged as records (exchange_pairs).
  subroutine mortar_pairs(contact, it)
    type(mortar_contact_t), intent(in) :: contact     !< contact data
    type(contact_interface_t), intent(inout) :: it    !< the interface
    real(wp) :: xs(3, 3), xm(3, MAX_VERTICES), overlap, n_s(3), n_m(3), facing
    integer :: k, s, m, i, nm, first, last
    first = 1
    last = it%ncandidate
    if (it%divided) then
      first = int(int(it%ncandidate, i8)*contact%rank/contact%nranks) + 1
      last = int(int(it%ncandidate, i8)*(contact%rank + 1)/contact%nranks)
    end if
    ! the slave facets of the slice are a range (the candidates are sorted by slave facet)
    if (.not. allocated(it%slave_normal)) allocate(it%slave_normal(3, it%slave%nfacet))
    if (first <= last) call facet_unit_normals(it%slave, contact%x, it%candidates(1, first), &
                                               it%candidates(1, last), it%slave_normal)
    call facet_unit_normals(it%master, contact%x, 1, it%master%nfacet, it%master_normal_f)
    if (.not. allocated(it%pairs)) allocate(it%pairs(0))
    if (size(it%pairs) < it%ncandidate) then       ! grows, never shrinks: no reallocation
      deallocate(it%pairs)                          ! once the contact has settled
      allocate(it%pairs(it%ncandidate + it%ncandidate/2))
    end if
    it%npair = 0
    do k = first, last
      s = it%candidates(1, k)
      m = it%candidates(2, k)
      ! partners face each other: an outward master facet against the slave normal within
      ! FACING_ANGLE (the far side of a master body, or a side face seen edge-on, is not a
      ! partner); a shell master facet (either orientation) nearly parallel to the slave
      n_s = it%slave_normal(:, s)
      n_m = it%master_normal_f(:, m)
      facing = dot_product(n_s, n_m)
      if (.not. it%master%outward(m)) facing = -abs(facing)
      if (facing > -FACING_COSINE) cycle
      nm = it%master%nvertex(m)
      if (it%single) then
        if (.not. it%slave%outward(s)) cycle          ! shells are masters only
        if (too_deep(contact, it, s, m, n_m)) cycle
      end if
      associate (p => it%pairs(it%npair + 1))
        p%candidate = k
        p%slave = s
        p%master = m
        if (contact%dim == 2) then
          p%n_ab = 0.0_wp
          p%n_ac = 0.0_wp
          call mortar_segment_pair_2d(contact%x(1:2, it%slave%facets(1:2, s)), &
                                      contact%x(1:2, it%master%facets(1:2, m)), &
                                      p%n_ab(1:2, 1:2), p%n_ac(1:2, 1:2), overlap)
        else
          do i = 1, 3
            xs(:, i) = contact%x(:, it%slave%facets(i, s))
          end do
          xm = 0.0_wp
          do i = 1, nm
            xm(:, i) = contact%x(:, it%master%facets(i, m))
          end do
          call mortar_triangle_pair_3d(xs, xm, nm, p%n_ab, p%n_ac, overlap)
          if (it%slave%weight(s) /= 1.0_wp) then   ! a triangle of a quadrilateral
            p%n_ab = it%slave%weight(s)*p%n_ab
            p%n_ac = it%slave%weight(s)*p%n_ac
            overlap = it%slave%weight(s)*overlap
          end if
        end if
        if (overlap <= 0.0_wp) cycle
        p%master_normal = n_m/max(norm2(n_m), tiny(1.0_wp))
        if (dot_product(p%master_normal, n_s) > 0.0_wp) p%master_normal = -p%master_normal
      end associate
      it%npair = it%npair + 1
    end do
    if (it%divided) call exchange_pairs(it)
  end subroutine mortar_pairs

  !> Every rank's pairs on every rank: this rank's pairs (it%pairs(1:npair)) packed into
  !> records of PAIR_RECORD_LENGTH reals, the records of all ranks concatenated in rank order
  !> (one allgatherv), unpacked into it%pairs. The slices are contiguous and in rank order,
  !> so the result is the pair list in global candidate order, the same bits as on one rank.
  subroutine exchange_pairs(it)
    type(contact_interface_t), intent(inout) :: it    !< the interface
    integer :: q, o, i, j, k, n_values
    if (.not. allocated(it%records)) allocate(it%records(PAIR_RECORD_LENGTH*size(it%pairs)))
    if (size(it%records) < PAIR_RECORD_LENGTH*it%npair) then
      deallocate(it%records)
      allocate(it%records(PAIR_RECORD_LENGTH*size(it%pairs)))
    end if
    do q = 1, it%npair
      o = (q - 1)*PAIR_RECORD_LENGTH
      associate (p => it%pairs(q))
        it%records(o + 1) = real(p%candidate, wp)
        do j = 1, 3
          do i = 1, 3
            it%records(o + 1 + i + 3*(j - 1)) = p%n_ab(i, j)
          end do
        end do
        do j = 1, MAX_VERTICES
          do i = 1, 3
            it%records(o + 10 + i + 3*(j - 1)) = p%n_ac(i, j)
          end do
        end do
        it%records(o + 11 + 3*MAX_VERTICES:o + 13 + 3*MAX_VERTICES) = p%master_normal
      end associate
    end do
    call comm_allgatherv_real(it%records, PAIR_RECORD_LENGTH*it%npair, it%all_records, n_values)
    it%npair = n_values/PAIR_RECORD_LENGTH
    do q = 1, it%npair
      o = (q - 1)*PAIR_RECORD_LENGTH
      associate (p => it%pairs(q))
        k = nint(it%all_records(o + 1))
        p%candidate = k
        p%slave = it%candidates(1, k)
        p%master = it%candidates(2, k)
        do j = 1, 3
          do i = 1, 3
            p%n_ab(i, j) = it%all_records(o + 1 + i + 3*(j - 1))
          end do
        end do
        do j = 1, MAX_VERTICES
          do i = 1, 3
            p%n_ac(i, j) = it%all_records(o + 10 + i + 3*(j - 1))
          end do
        end do
        p%master_normal = it%all_records(o + 11 + 3*MAX_VERTICES:o + 13 + 3*MAX_VERTICES)
      end associate
    end do
  end subroutine exchange_pairs

  !> Per slave node, the weighted gap vector G_A = sum_C n_AC x_C - sum_B n_AB x_B of a set
  !> of pairs at positions x, and optionally A_A = sum_B n_AB. (Each node's running sum is
  !> held in locals within a pair; the order of the additions is that of the pairs.)
  subroutine weighted_sums(x, it, pairs, npair, first, last, gap_vector, area)
    real(wp), intent(in) :: x(:,:)                    !< (3, mesh nodes) positions
    type(contact_interface_t), intent(in) :: it       !< the interface
    type(pair_t), intent(in) :: pairs(:)              !< pairs
    integer, intent(in) :: npair                      !< pairs used
    integer, intent(in) :: first, last                !< slave nodes wanted (others: 0)
    real(wp), intent(out) :: gap_vector(:,:)          !< (3, slave nodes)
    real(wp), intent(out), optional :: area(:)        !< (slave nodes)
    integer :: k, a, b, c, na, nm, slot, s, m, node
    real(wp) :: g(3), w, sum_weights
    logical :: with_area
    with_area = present(area)
    gap_vector = 0.0_wp
    if (with_area) area = 0.0_wp
    do k = 1, npair
      s = pairs(k)%slave
      m = pairs(k)%master
      na = it%slave%nvertex(s)
      nm = it%master%nvertex(m)
      do a = 1, na
        slot = it%slave%local(a, s)
        if (slot < first .or. slot > last) cycle
        g = gap_vector(:, slot)
        do b = 1, na
          node = it%slave%facets(b, s)
          w = pairs(k)%n_ab(a, b)
          g(1) = g(1) - w*x(1, node)
          g(2) = g(2) - w*x(2, node)
          g(3) = g(3) - w*x(3, node)
        end do
        do c = 1, nm
          node = it%master%facets(c, m)
          w = pairs(k)%n_ac(a, c)
          g(1) = g(1) + w*x(1, node)
          g(2) = g(2) + w*x(2, node)
          g(3) = g(3) + w*x(3, node)
        end do
        gap_vector(:, slot) = g
        if (with_area) then
          sum_weights = area(slot)
          do b = 1, na
            sum_weights = sum_weights + pairs(k)%n_ab(a, b)
          end do
          area(slot) = sum_weights
        end if
      end do
    end do
  end subroutine weighted_sums

  !> Nodal forces of the interface's traction tau_A = -p_A n_A + t_A, added to contact%force:
  !> slave f_B += sum_A n_AB tau_A, master f_C -= sum_A n_AC tau_A; and their resultants.
  !> (Running sums in locals; the order of the additions is that of the pairs.)
  subroutine nodal_forces(contact, it)
    type(mortar_contact_t), intent(inout) :: contact  !< contact data
    type(contact_interface_t), intent(inout) :: it    !< the interface
    real(wp) :: tau(3, 3), total_slave(3), total_master(3)
    integer :: k, a, b, c, na, nm, node, slot, s, m
    total_slave = 0.0_wp
    total_master = 0.0_wp
    do k = 1, it%npair
      s = it%pairs(k)%slave
      m = it%pairs(k)%master
      na = it%slave%nvertex(s)
      nm = it%master%nvertex(m)
      do a = 1, na
        slot = it%slave%local(a, s)
        tau(:, a) = -it%pressure(slot)*it%normal(:, slot) + it%traction(:, slot)
      end do
      do b = 1, na
        node = contact%node_index(it%slave%facets(b, s))
        call add_weighted_tractions(na, 1.0_wp, it%pairs(k)%n_ab(:, b), tau, &
                                    contact%force(:, node), total_slave)
      end do
      do c = 1, nm
        node = contact%node_index(it%master%facets(c, m))
        call add_weighted_tractions(na, -1.0_wp, it%pairs(k)%n_ac(:, c), tau, &
                                    contact%force(:, node), total_master)
      end do
    end do
    it%force_slave = total_slave
    it%force_master = total_master
  end subroutine nodal_forces

  !> One node's share of a pair: force += side sum_a w_a tau_a, and the same into the side's
  !> total (side = +1 slave, -1 master: the reaction; the sign is exact, so the bits are those
  !> of adding or subtracting w_a tau_a).
  pure subroutine add_weighted_tractions(na, side, weights, tau, force, total)
    integer, intent(in) :: na                      !< slave facet vertices
    real(wp), intent(in) :: side                   !< +1 (slave) or -1 (master)
    real(wp), intent(in) :: weights(:)             !< (na) mortar weights of the node
    real(wp), intent(in) :: tau(:,:)               !< (3, na) slave-node tractions
    real(wp), intent(inout) :: force(3)            !< the node's force
    real(wp), intent(inout) :: total(3)            !< the side's resultant
    real(wp) :: f(3), w
    integer :: a
    f = force
    do a = 1, na
      w = side*weights(a)
      f = f + w*tau(:, a)
      total = total + w*tau(:, a)
    end do
    force = f
  end subroutine add_weighted_tractions


  !> Write the state a contact carries from one call to the next into a restart file (the
  !> data are replicated: rank 0 writes): per interface the search (candidates, positions at
  !> the search), the last call's pairs with their mortar weights, the slave nodes' areas,
  !> normals, tractions (friction history) and offsets, the tiebreak's held nodes.
  subroutine mortar_contact_restart_put(contact, f)
    type(mortar_contact_t), intent(in) :: contact     !< contact data after a call
    type(restart_file_t), intent(inout) :: f          !< file being written
    integer :: k, q, ns
    call restart_put_ints(f, 'contact.interfaces', 1, [contact%n])
    do k = 1, contact%n
      associate (it => contact%interfaces(k))
        ns = size(it%slave%nodes)
        call restart_put_ints(f, 'contact.flags', 5, [merge(1, 0, it%searched), &
            merge(1, 0, it%evaluated), merge(1, 0, it%eroded), it%ncandidate, it%npair])
        call restart_put_ints(f, 'contact.candidates', 2*it%ncandidate, &
                              it%candidates(:, 1:it%ncandidate))
        if (it%searched) call restart_put_reals(f, 'contact.search_positions', &
                                                size(it%x_search), it%x_search)
        call restart_put_ints(f, 'contact.pair_facets', 3*it%npair, &
            [(it%pairs(q)%candidate, it%pairs(q)%slave, it%pairs(q)%master, q = 1, it%npair)])
        call restart_put_reals(f, 'contact.pair_weights', PAIR_REALS*it%npair, &
            [(pair_values(it%pairs(q)), q = 1, it%npair)])
        call restart_put_reals(f, 'contact.nodes', 13*ns, [it%area, it%normal, &
            it%master_normal, it%traction, it%traction_local, it%offset])
        call restart_put_reals(f, 'contact.penalty', 2, [it%eps_material, it%mass_per_area])
        if (allocated(it%held)) call restart_put_ints(f, 'contact.held', ns, &
                                                      merge(1, 0, it%held))
      end associate
    end do
  contains
    !> A pair's reals, flat.
    pure function pair_values(p) result(r)
      type(pair_t), intent(in) :: p                   !< the pair
      real(wp) :: r(PAIR_REALS)
      r = [reshape(p%n_ab, [9]), reshape(p%n_ac, [3*MAX_VERTICES]), p%master_normal]
    end function pair_values
  end subroutine mortar_contact_restart_put

  !> Read what mortar_contact_restart_put wrote into contact data set up for the same model
  !> (every rank).
  subroutine mortar_contact_restart_get(contact, f)
    type(mortar_contact_t), intent(inout) :: contact  !< contact data, set up
    type(restart_file_t), intent(inout) :: f          !< file being read
    integer :: k, q, ns, n(1), flags(5)
    integer, allocatable :: facets(:), held(:)
    real(wp), allocatable :: weights(:), nodes(:)
    real(wp) :: penalty(2)
    call restart_get_ints(f, 'contact.interfaces', 1, n)
    do k = 1, contact%n
      associate (it => contact%interfaces(k))
        ns = size(it%slave%nodes)
        call restart_get_ints(f, 'contact.flags', 5, flags)
        it%searched = flags(1) == 1
        it%evaluated = flags(2) == 1
        it%eroded = flags(3) == 1
        it%ncandidate = flags(4)
        it%npair = flags(5)
        if (allocated(it%candidates)) deallocate(it%candidates)
        allocate(it%candidates(2, max(it%ncandidate, 1)))
        call restart_get_ints(f, 'contact.candidates', 2*it%ncandidate, it%candidates)
        if (it%searched) then
          if (.not. allocated(it%x_search)) allocate(it%x_search(3, size(it%surface_nodes)))
          call restart_get_reals(f, 'contact.search_positions', size(it%x_search), &
                                 it%x_search)
        end if
        call restart_get_ints_alloc(f, 'contact.pair_facets', facets)
        call restart_get_reals_alloc(f, 'contact.pair_weights', weights)
        if (size(it%pairs) < it%npair) then
          deallocate(it%pairs)
          allocate(it%pairs(it%npair))
        end if
        do q = 1, it%npair
          it%pairs(q)%candidate = facets(3*q - 2)
          it%pairs(q)%slave = facets(3*q - 1)
          it%pairs(q)%master = facets(3*q)
          associate (r => weights(PAIR_REALS*(q - 1) + 1:PAIR_REALS*q))
            it%pairs(q)%n_ab = reshape(r(1:9), [3, 3])
            it%pairs(q)%n_ac = reshape(r(10:9 + 3*MAX_VERTICES), [3, MAX_VERTICES])
            it%pairs(q)%master_normal = r(PAIR_REALS - 2:PAIR_REALS)
          end associate
        end do
        allocate(nodes(13*ns))
        call restart_get_reals(f, 'contact.nodes', 13*ns, nodes)
        it%area = nodes(1:ns)
        it%normal = reshape(nodes(ns + 1:4*ns), [3, ns])
        it%master_normal = reshape(nodes(4*ns + 1:7*ns), [3, ns])
        it%traction = reshape(nodes(7*ns + 1:10*ns), [3, ns])
        it%traction_local = reshape(nodes(10*ns + 1:12*ns), [2, ns])
        it%offset = nodes(12*ns + 1:13*ns)
        deallocate(nodes)
        call restart_get_reals(f, 'contact.penalty', 2, penalty)
        it%eps_material = penalty(1)
        it%mass_per_area = penalty(2)
        if (allocated(it%held)) then
          allocate(held(ns))
          call restart_get_ints(f, 'contact.held', ns, held)
          it%held = held == 1
          deallocate(held)
        end if
      end associate
    end do
  end subroutine mortar_contact_restart_get

end module mefem_mortar_contact
