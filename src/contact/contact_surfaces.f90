!> Contact surfaces and the candidate search of the mortar contact (SURFA = slave, SURFB =
!> master of *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE(_MORTAR)).
!>
!> contact_surface_build turns a contact target (segment set, part or part set) into a list of
!> facets: 2-node edges in 2D, 3-node triangles or 4-node quadrilaterals in 3D, holding global
!> mesh node indices, with the distinct surface nodes (ascending) and each facet's local
!> numbering into them. Orientation: the facet normal points out of its body:
!> - 3D: vertices counter-clockwise seen from outside, (x2 - x1) x (x3 - x1) outward;
!> - 2D: edge N1 -> N2 with the body on the left, outward normal (t_y, -t_x), t = x2 - x1.
!> Faces of solids (and 2D edges of in-plane elements) are oriented against the centroid of
!> their element. Shells of 3D parts (rigid tools) become facets with the element's own node
!> order, whose side is not knowable here: such facets carry outward = .false., and the mortar
!> kernel must accept either orientation of a master facet.
!>
!> contact_search_build finds the candidate (slave facet, master facet) pairs whose bounding
!> boxes overlap once the master boxes are enlarged by a margin, through a uniform grid of
!> cells (bucket sort) sized by the mean master facet: O(n) in facets, the pairs sorted by
!> slave then master facet. The grid arrays live in a contact_search_t and are reused.
module mefem_contact_surfaces
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa
  use mefem_vector_math, only: cross
  use mefem_output_mesh, only: NODES_OF_TOPO
  use mefem_model, only: model_t, ELEM_SOLID, ELEM_SHELL, SET_SEGMENT, SET_PART, &
                         SURFACE_SEGMENT_SET, SURFACE_PART_SET, SURFACE_PART, &
                         SURFACE_NODE_SET, SURFACE_ALL_PARTS, SURFACE_ALL_BUT_SET, SET_NODE, &
                         TOPO_TRI3, TOPO_QUAD4, TOPO_TET4, TOPO_PENTA6, TOPO_HEX8
  implicit none
  private

  public :: contact_surface_build, contact_surface_pair_build, contact_facet_area_vector, &
            contact_surface_triangulate
  public :: contact_search_build, exterior_nodes, contact_parts_to_facets


  !> Most vertices of a facet and most faces of an element.
  integer, parameter :: MAX_VERTICES = 4, MAX_FACES = 6
  !> The grid holds at most this many cells per master facet (guards against a sparse master
  !> surface in a large box, e.g. two far-apart plates); cells then grow beyond the mean size.
  integer, parameter :: MAX_CELLS_PER_FACET = 32
  !> Factor by which capped cells are widened until their count fits the cap.
  real(wp), parameter :: CELL_WIDENING = 1.05_wp
  !> Growth factor of reused arrays that must grow (amortises slowly growing sizes).
  real(wp), parameter :: GROWTH = 1.5_wp
  !> Candidate lists up to this length are sorted by insertion, longer ones by heapsort.
  integer, parameter :: INSERTION_SORT_MAX = 32

  ! Faces of the solids, corners in output (VTK) order, each a cycle around the face.
  integer, parameter :: TET_FACES(3, 4) = reshape([1, 2, 3,  1, 2, 4,  2, 3, 4,  1, 3, 4], &
                                                  [3, 4])
  integer, parameter :: PENTA_FACES(4, 5) = reshape([1, 2, 3, 0,  4, 5, 6, 0,  1, 2, 5, 4, &
                                                     2, 3, 6, 5,  3, 1, 4, 6], [4, 5])
  integer, parameter :: PENTA_FACE_NV(5) = [3, 3, 4, 4, 4]
  integer, parameter :: HEX_FACES(4, 6) = reshape([1, 2, 3, 4,  5, 6, 7, 8,  1, 2, 6, 5, &
                                                   2, 3, 7, 6,  3, 4, 8, 7,  4, 1, 5, 8], [4, 6])

  !> The facets of one contact surface.
  type, public :: contact_surface_t
    integer :: dim = 3                      !< 2 (edges) or 3 (triangles and quadrilaterals)
    integer :: nfacet = 0                   !< number of facets
    integer, allocatable :: facets(:,:)     !< (4, nfacet) global node indices, 0 = unused
    integer, allocatable :: nvertex(:)      !< (nfacet) 2 (2D edge), 3 or 4
    integer, allocatable :: element(:)      !< (nfacet) owning (adjacent) element, 0 = none
    integer, allocatable :: neighbour(:)    !< (nfacet) a face inside the body (eroding
                                            !< contacts): the element on its other side, whose
                                            !< erosion exposes it; 0 = a face of the boundary
    logical, allocatable :: outward(:)      !< (nfacet) orientation known to be outward
    integer :: nnode = 0                    !< distinct surface nodes
    integer, allocatable :: nodes(:)        !< (nnode) their global indices, ascending
    integer, allocatable :: local(:,:)      !< (4, nfacet) positions in nodes, 0 = unused
    integer, allocatable :: pieces(:)       !< (nfacet) its share of its face's area: 1 whole,
                                            !< 2 half (contact_surface_triangulate)
    real(wp), allocatable :: weight(:)      !< (nfacet) its weight in the surface integrals
                                            !< (1; 1/2 for the triangles of a quadrilateral)
  end type contact_surface_t

  !> The bucket grid of the candidate search, kept between calls.
  type, public :: contact_search_t
    integer :: dim = 3                      !< dimensions binned (2 or 3)
    real(wp) :: cell_size = 0.0_wp          !< edge of a cubic (square) cell
    real(wp) :: origin(3) = 0.0_wp          !< lower corner of the grid
    integer :: ncell(3) = 1                 !< cells per direction (1 in z for 2D)
    integer, allocatable :: cell_start(:)   !< (cells + 1) cell c holds cell_master(cell_start(c):
                                            !< cell_start(c+1)-1)
    integer, allocatable :: cell_master(:)  !< master facets binned, ascending within a cell
    real(wp), allocatable :: lo(:,:), hi(:,:)  !< (3, nmaster) master boxes with the margin
    integer, allocatable :: stamp(:)        !< (nmaster) last slave facet that met a master
    integer, allocatable :: found(:)        !< candidate masters of one slave facet
    integer :: n_grows = 0                  !< times a work array was (re)allocated
    integer(i8) :: n_box_tests = 0          !< box overlap tests of the last call
  end type contact_search_t

contains

  ! ====================================================================== surfaces

  !> The facets of a contact surface: kind is SURFATYP or SURFBTYP as stored in contact_t
  !> (0 segment set, 2 part set, 3 part), target the resolved set or part index. Fails (status)
  !> on an unknown kind or target, a set of the wrong kind, a segment that does not fit the
  !> model's dimension, solids in a 2D model, or an empty surface; label (e.g. 'contact 5
  !> SURFA') prefixes the messages.
  subroutine contact_surface_build(model, kind, target, surface, status, label, interior)
    type(model_t), intent(in) :: model                !< the resolved model
    integer, intent(in) :: kind                       !< SURFACE_* code
    integer, intent(in) :: target                     !< set or part index
    type(contact_surface_t), intent(out) :: surface   !< the surface
    type(status_t), intent(out) :: status             !< failure and message
    character(len=*), intent(in), optional :: label   !< what the surface is, for messages
    logical, intent(in), optional :: interior         !< parts: with the faces inside (eroding
                                                      !< contacts: contact_parts_to_facets)
    character(len=:), allocatable :: who
    logical, allocatable :: selected(:)
    who = 'contact surface'
    if (present(label)) who = label
    surface%dim = model%dimension
    select case (kind)
    case (SURFACE_SEGMENT_SET)
      if (.not. valid_set(model, target, SET_SEGMENT)) then
        call fail(status, who//': target '//itoa(target)//' is not a segment set')
        return
      end if
      call segments_to_facets(model, target, surface, status, who)
    case (SURFACE_PART, SURFACE_PART_SET, SURFACE_ALL_PARTS, SURFACE_ALL_BUT_SET)
      allocate(selected(model%n_parts))
      selected = .false.
      if (kind == SURFACE_ALL_PARTS) then
        selected = .true.
      else if (kind == SURFACE_PART) then
        if (target < 1 .or. target > model%n_parts) then
          call fail(status, who//': target '//itoa(target)//' is not a part')
          return
        end if
        selected(target) = .true.
      else
        if (.not. valid_set(model, target, SET_PART)) then
          call fail(status, who//': target '//itoa(target)//' is not a part set')
          return
        end if
        if (any(model%sets(target)%members < 1 .or. &
                model%sets(target)%members > model%n_parts)) then
          call fail(status, who//': part set '//itoa(model%sets(target)%id)// &
                    ' holds an unresolved part')
          return
        end if
        selected(model%sets(target)%members) = .true.
        if (kind == SURFACE_ALL_BUT_SET) selected = .not. selected
      end if
      call contact_parts_to_facets(model, selected, surface, status, who//' ('// &
                           target_name(model, kind, target)//')', interior)
    case (SURFACE_NODE_SET)
      ! nodes-to-surface contacts: the exterior faces (2D: boundary edges) of all parts whose
      ! vertices are all in the node set
      if (.not. valid_set(model, target, SET_NODE)) then
        call fail(status, who//': target '//itoa(target)//' is not a node set')
        return
      end if
      allocate(selected(model%n_parts))
      selected = .true.
      call contact_parts_to_facets(model, selected, surface, status, who//' ('// &
                           target_name(model, kind, target)//')', interior)
      if (status%ok) call keep_facets_of_nodes(model, model%sets(target)%members, surface)
    case default
      call fail(status, who//': surface type '//itoa(kind)//' is not supported '// &
                '(0 segment set, 2 part set, 3 part, 4 node set, 5 all parts, 6 all but a '// &
                'part set)')
      return
    end select
    if (.not. status%ok) return
    if (surface%nfacet == 0) then
      call fail(status, who//': '//target_name(model, kind, target)//' gives no contact '// &
          'facets (no segments, exterior solid faces, shells or boundary edges)')
      return
    end if
    call number_nodes(model%nodes%n, surface)
  end subroutine contact_surface_build

  !> Slave (SURFA) and master (SURFB) surfaces of contact k of the model; messages name the
  !> contact by its id (or its position when it has none) and SURFA/SURFB. A single-surface
  !> contact's master is its SURFA again (the same facets, in the same order).
  subroutine contact_surface_pair_build(model, k, slave, master, status)
    type(model_t), intent(in) :: model                !< the resolved model
    integer, intent(in) :: k                          !< contact index in model%contacts
    type(contact_surface_t), intent(out) :: slave     !< SURFA facets
    type(contact_surface_t), intent(out) :: master    !< SURFB facets
    type(status_t), intent(out) :: status             !< failure and message
    character(len=:), allocatable :: who
    associate (contact => model%contacts(k))
      if (contact%id /= 0) then
        who = 'contact '//itoa(contact%id)
      else
        who = 'contact number '//itoa(k)//' (no id)'
      end if
      call contact_surface_build(model, contact%surf_a_type, contact%surf_a, slave, status, &
                                 who//' SURFA', contact%eroding)
      if (.not. status%ok) return
      if (contact%single_surface) then
        master = slave
        return
      end if
      call contact_surface_build(model, contact%surf_b_type, contact%surf_b, master, status, &
                                 who//' SURFB', contact%eroding)
    end associate
  end subroutine contact_surface_pair_build

  !> Replace every quadrilateral facet of a 3D surface by the four triangles of its two
  !> triangulations, (N1 N2 N3) (N1 N3 N4) and (N1 N2 N4) (N2 N3 N4), each of weight 1/2: the
  !> mortar slave side integrates over triangles, and the mean of the two triangulations
  !> gives every corner of a flat quadrilateral a quarter of its area (one triangulation alone
  !> gives a third and a sixth at alternate corners: a uniform pressure would push the
  !> hourglass mode of a one-point hexahedron). The triangles keep the facet's element,
  !> orientation and vertex order, in the facet's place; pieces = 2 (each is half the face),
  !> weight 1/2. Other facets: pieces 1, weight 1.
  subroutine contact_surface_triangulate(surface)
    type(contact_surface_t), intent(inout) :: surface   !< the surface
    integer, parameter :: TRIANGLES(3, 4) = reshape([1, 2, 3,  1, 3, 4,  1, 2, 4,  2, 3, 4], &
                                                    [3, 4])
    integer, allocatable :: facets(:,:), nvertex(:), element(:), local(:,:), pieces(:)
    integer, allocatable :: neighbour(:)
    logical, allocatable :: outward(:)
    real(wp), allocatable :: weight(:)
    integer :: f, n, k
    if (.not. allocated(surface%pieces)) then
      allocate(surface%pieces(surface%nfacet), surface%weight(surface%nfacet))
      surface%pieces = 1
      surface%weight = 1.0_wp
    end if
    if (.not. allocated(surface%neighbour)) then
      allocate(surface%neighbour(surface%nfacet))
      surface%neighbour = 0
    end if
    if (surface%dim /= 3 .or. all(surface%nvertex /= 4)) return
    n = surface%nfacet + 3*count(surface%nvertex == 4)
    allocate(facets(MAX_VERTICES, n), nvertex(n), element(n), local(MAX_VERTICES, n), &
             pieces(n), outward(n), weight(n), neighbour(n))
    n = 0
    do f = 1, surface%nfacet
      if (surface%nvertex(f) /= 4) then
        n = n + 1
        facets(:, n) = surface%facets(:, f)
        nvertex(n) = surface%nvertex(f)
        local(:, n) = surface%local(:, f)
        element(n) = surface%element(f)
        neighbour(n) = surface%neighbour(f)
        outward(n) = surface%outward(f)
        pieces(n) = surface%pieces(f)
        weight(n) = surface%weight(f)
        cycle
      end if
      do k = 1, size(TRIANGLES, 2)
        n = n + 1
        facets(:, n) = 0
        local(:, n) = 0
        facets(1:3, n) = surface%facets(TRIANGLES(:, k), f)
        local(1:3, n) = surface%local(TRIANGLES(:, k), f)
        nvertex(n) = 3
        element(n) = surface%element(f)
        neighbour(n) = surface%neighbour(f)
        outward(n) = surface%outward(f)
        pieces(n) = 2
        weight(n) = 0.5_wp
      end do
    end do
    surface%nfacet = n
    call move_alloc(facets, surface%facets)
    call move_alloc(nvertex, surface%nvertex)
    call move_alloc(element, surface%element)
    call move_alloc(neighbour, surface%neighbour)
    call move_alloc(local, surface%local)
    call move_alloc(pieces, surface%pieces)
    call move_alloc(outward, surface%outward)
    call move_alloc(weight, surface%weight)
  end subroutine contact_surface_triangulate

  !> Area vector of facet f at coordinates x (rows 1:dim used): |a| = area (3D) or length
  !> (2D), direction = the facet normal (outward for outward facets); a(3) = 0 in 2D.
  pure function contact_facet_area_vector(surface, f, x) result(a)
    type(contact_surface_t), intent(in) :: surface   !< the surface
    integer, intent(in) :: f                         !< facet index
    real(wp), intent(in) :: x(:,:)                   !< (3 or dim, nnodes) coordinates
    real(wp) :: a(3)
    real(wp) :: xv(3, MAX_VERTICES)
    integer :: i, nv
    nv = surface%nvertex(f)
    xv = 0.0_wp
    do i = 1, nv
      xv(1:surface%dim, i) = x(1:surface%dim, surface%facets(i, f))
    end do
    a = area_vector(nv, xv)
  end function contact_facet_area_vector

  !> Area vector of a polygon of nv vertices (nv = 2: the 2D edge normal (t_y, -t_x, 0)).
  pure function area_vector(nv, xv) result(a)
    integer, intent(in) :: nv                 !< 2, 3 or 4
    real(wp), intent(in) :: xv(3, MAX_VERTICES)  !< vertices
    real(wp) :: a(3)
    select case (nv)
    case (2)
      a = [xv(2, 2) - xv(2, 1), xv(1, 1) - xv(1, 2), 0.0_wp]
    case (3)
      a = 0.5_wp*cross(xv(:, 2) - xv(:, 1), xv(:, 3) - xv(:, 1))
    case default
      a = 0.5_wp*cross(xv(:, 3) - xv(:, 1), xv(:, 4) - xv(:, 2))
    end select
  end function area_vector

  !> Segments of a segment set as facets, oriented against the adjacent solid (3D) or
  !> in-plane element (2D) when there is one, else kept as given.
  subroutine segments_to_facets(model, s, surface, status, who)
    type(model_t), intent(in) :: model                  !< the model
    integer, intent(in) :: s                            !< segment set index
    type(contact_surface_t), intent(inout) :: surface   !< facets filled in
    type(status_t), intent(inout) :: status             !< failure and message
    character(len=*), intent(in) :: who                 !< message prefix
    integer, allocatable :: start(:), around(:)
    integer :: i, nseg, seg(4), nv, e
    logical :: body
    character(len=:), allocatable :: shape
    associate (set => model%sets(s))
      nseg = set%n
      call allocate_facets(surface, nseg)
      call node_elements(model, start, around)
      do i = 1, nseg
        seg = set%members(4*i-3:4*i)
        nv = segment_vertices(seg, model%dimension)
        if (nv == 0 .or. any(seg(1:max(nv, 1)) <= 0)) then
          if (model%dimension == 2) then
            shape = 'a line (N1 N2) in a 2D model'
          else
            shape = 'a triangle or quadrilateral in a 3D model'
          end if
          call fail(status, who//': segment '//itoa(i)//' of segment set '//itoa(set%id)// &
              ' (nodes '//itoa(set%member_ids(4*i-3))//' '//itoa(set%member_ids(4*i-2))// &
              ' '//itoa(set%member_ids(4*i-1))//' '//itoa(set%member_ids(4*i))// &
              ') is not '//shape)
          return
        end if
        call adjacent_element(model, start, around, seg(1:nv), e, body)
        surface%nfacet = i
        surface%facets(:, i) = 0
        surface%facets(1:nv, i) = seg(1:nv)
        surface%nvertex(i) = nv
        surface%element(i) = e
        surface%outward(i) = body
        if (body) call orient_outward(model, e, surface%facets(:, i), nv)
      end do
    end associate
  end subroutine segments_to_facets

  !> Vertices of a stored segment (N1 N2 N2 N2 or N1 N2 0 0 a 2D line; N4 = N3 or 0 a
  !> triangle; else a quadrilateral); 0 when it does not fit the dimension.
  pure integer function segment_vertices(seg, dim)
    integer, intent(in) :: seg(4)     !< node indices as stored
    integer, intent(in) :: dim        !< model dimension
    logical :: line
    line = (seg(3) == 0 .or. seg(3) == seg(2)) .and. (seg(4) == 0 .or. seg(4) == seg(2))
    segment_vertices = 0
    if (dim == 2) then
      if (line) segment_vertices = 2
    else if (.not. line .and. seg(3) /= 0 .and. seg(3) /= seg(2)) then
      segment_vertices = 4
      if (seg(4) == 0 .or. seg(4) == seg(3)) segment_vertices = 3
    end if
  end function segment_vertices

  !> Elements around each node: around(start(n):start(n+1)-1), ascending.
  subroutine node_elements(model, start, around)
    type(model_t), intent(in) :: model                 !< the model
    integer, allocatable, intent(out) :: start(:)      !< (nnodes + 1) offsets
    integer, allocatable, intent(out) :: around(:)     !< element indices
    integer :: e, i, n, nn
    allocate(start(model%nodes%n + 1))
    start = 0
    do e = 1, model%elements%n
      nn = NODES_OF_TOPO(model%elements%topology(e))
      do i = 1, nn
        n = model%elements%conn(i, e)
        start(n + 1) = start(n + 1) + 1
      end do
    end do
    start(1) = 1
    do n = 1, model%nodes%n
      start(n + 1) = start(n + 1) + start(n)
    end do
    allocate(around(start(model%nodes%n + 1) - 1))
    do e = 1, model%elements%n
      nn = NODES_OF_TOPO(model%elements%topology(e))
      do i = 1, nn
        n = model%elements%conn(i, e)
        around(start(n)) = e
        start(n) = start(n) + 1
      end do
    end do
    do n = model%nodes%n, 1, -1
      start(n + 1) = start(n)
    end do
    start(1) = 1
  end subroutine node_elements

  !> The element a segment bounds: in 3D the first solid with the segment as a face (body =
  !> .true.), else the first shell with exactly its nodes (body = .false.); in 2D the first
  !> element with the segment as an edge (body = .true.). e = 0 when there is none.
  subroutine adjacent_element(model, start, around, seg, e, body)
    type(model_t), intent(in) :: model           !< the model
    integer, intent(in) :: start(:), around(:)   !< elements around nodes
    integer, intent(in) :: seg(:)                !< segment nodes
    integer, intent(out) :: e                    !< adjacent element or 0
    logical, intent(out) :: body                 !< e is a body the segment bounds
    integer :: k, el, nface, f, nv(MAX_FACES), pos(MAX_VERTICES, MAX_FACES), key(4), fkey(4)
    integer :: shell
    e = 0
    body = .false.
    shell = 0
    key = sorted_key(seg)
    do k = start(seg(1)), start(seg(1) + 1) - 1
      el = around(k)
      call element_faces(model, el, nface, nv, pos)
      do f = 1, nface
        if (nv(f) /= size(seg)) cycle
        fkey = sorted_key(model%elements%conn(pos(1:nv(f), f), el))
        if (all(fkey == key)) then
          e = el
          body = .true.
          return
        end if
      end do
      if (model%dimension == 3 .and. model%elements%keyword(el) == ELEM_SHELL .and. &
          shell == 0) then
        if (NODES_OF_TOPO(model%elements%topology(el)) == size(seg)) then
          fkey = sorted_key(model%elements%conn(1:size(seg), el))
          if (all(fkey == key)) shell = el
        end if
      end if
    end do
    e = shell
  end subroutine adjacent_element

  !> The nodes on the exterior faces of the model's solids (faces met once among all
  !> solid elements; in 2D the boundary edges of the in-plane elements).
  subroutine exterior_nodes(model, on_surface)
    type(model_t), intent(in) :: model                  !< the model
    logical, allocatable, intent(out) :: on_surface(:)  !< (nodes) on an exterior face
    type(contact_surface_t) :: surface
    type(status_t) :: status
    logical, allocatable :: selected(:)
    integer :: f
    allocate(on_surface(model%nodes%n), selected(model%n_parts))
    on_surface = .false.
    selected = .true.
    if (model%dimension == 2) return                   ! (the hexahedra are 3D)
    call contact_parts_to_facets(model, selected, surface, status, 'exterior nodes')
    do f = 1, surface%nfacet
      on_surface(surface%facets(1:surface%nvertex(f), f)) = .true.
    end do
  end subroutine exterior_nodes

  !> Faces of an element that bound its body: faces of a 3D solid, edges of a 2D element
  !> (none for 3D shells and 2D solids). pos holds corner positions, a cycle per face.
  subroutine element_faces(model, e, nface, nv, pos)
    type(model_t), intent(in) :: model                   !< the model
    integer, intent(in) :: e                             !< element index
    integer, intent(out) :: nface                        !< faces
    integer, intent(out) :: nv(MAX_FACES)                !< vertices per face
    integer, intent(out) :: pos(MAX_VERTICES, MAX_FACES) !< corner positions
    integer :: f, nn
    nface = 0
    nv = 0
    pos = 0
    if (model%dimension == 2) then
      if (model%elements%keyword(e) /= ELEM_SHELL) return
      nn = NODES_OF_TOPO(model%elements%topology(e))
      nface = nn
      do f = 1, nn
        nv(f) = 2
        pos(1:2, f) = [f, modulo(f, nn) + 1]
      end do
      return
    end if
    if (model%elements%keyword(e) /= ELEM_SOLID) return
    select case (model%elements%topology(e))
    case (TOPO_TET4)
      nface = 4
      nv(1:4) = 3
      pos(1:3, 1:4) = TET_FACES
    case (TOPO_PENTA6)
      nface = 5
      nv(1:5) = PENTA_FACE_NV
      pos(:, 1:5) = PENTA_FACES
    case (TOPO_HEX8)
      nface = 6
      nv(1:6) = 4
      pos(:, 1:6) = HEX_FACES
    end select
  end subroutine element_faces

  !> Facets of the parts selected: exterior faces of solids (faces met once among the
  !> elements of those parts, oriented outward) and shells as they are in 3D; boundary edges in
  !> 2D (also used for segment sets by mefem_resolve_conditions). interior (eroding contacts):
  !> after them, every face between two of the solids twice, once as each element's face
  !> (oriented out of it, neighbour the other element), for the erosion of one to expose.
  subroutine contact_parts_to_facets(model, selected, surface, status, who, interior)
    type(model_t), intent(in) :: model                  !< the model
    logical, intent(in) :: selected(:)                  !< (n_parts) parts of the surface
    type(contact_surface_t), intent(inout) :: surface   !< facets filled in
    type(status_t), intent(inout) :: status             !< failure and message
    character(len=*), intent(in) :: who                 !< message prefix
    logical, intent(in), optional :: interior           !< add the faces inside (eroding)
    integer, allocatable :: face_nodes(:,:), face_nv(:), face_elem(:), keys(:,:)
    integer, allocatable :: start(:), bucket(:), other(:)
    logical, allocatable :: exterior(:)
    logical :: with_interior
    integer :: e, f, g, k, n, nface, nfaces, nshell, nv(MAX_FACES)
    integer :: pos(MAX_VERTICES, MAX_FACES), matches, nout
    ! count faces of the selected solids (2D: edges) and 3D shells
    nfaces = 0
    nshell = 0
    do e = 1, model%elements%n
      if (.not. selected(model%elements%part(e))) cycle
      if (model%dimension == 2 .and. model%elements%keyword(e) == ELEM_SOLID) then
        call fail(status, who//': element '//itoa(model%elements%id(e))//' is a solid in '// &
            'a 2D model; 2D contact surfaces are edges of in-plane shells')
        return
      end if
      if (model%dimension == 3 .and. model%elements%keyword(e) == ELEM_SHELL) then
        nshell = nshell + 1
      else
        call element_faces(model, e, nface, nv, pos)
        nfaces = nfaces + nface
      end if
    end do
    allocate(face_nodes(MAX_VERTICES, nfaces), face_nv(nfaces), face_elem(nfaces), &
             keys(MAX_VERTICES, nfaces))
    nfaces = 0
    do e = 1, model%elements%n
      if (.not. selected(model%elements%part(e))) cycle
      if (model%dimension == 3 .and. model%elements%keyword(e) == ELEM_SHELL) cycle
      call element_faces(model, e, nface, nv, pos)
      do f = 1, nface
        nfaces = nfaces + 1
        face_nodes(:, nfaces) = 0
        face_nodes(1:nv(f), nfaces) = model%elements%conn(pos(1:nv(f), f), e)
        face_nv(nfaces) = nv(f)
        face_elem(nfaces) = e
        keys(:, nfaces) = sorted_key(face_nodes(1:nv(f), nfaces))
      end do
    end do
    ! faces bucketed by their smallest node: a face is exterior when no other face of its
    ! bucket has the same nodes
    allocate(start(model%nodes%n + 1), bucket(nfaces), exterior(nfaces), other(nfaces))
    start = 0
    do f = 1, nfaces
      start(keys(1, f) + 1) = start(keys(1, f) + 1) + 1
    end do
    start(1) = 1
    do n = 1, model%nodes%n
      start(n + 1) = start(n + 1) + start(n)
    end do
    do f = 1, nfaces
      bucket(start(keys(1, f))) = f
      start(keys(1, f)) = start(keys(1, f)) + 1
    end do
    do n = model%nodes%n, 1, -1
      start(n + 1) = start(n)
    end do
    start(1) = 1
    other = 0
    do f = 1, nfaces
      matches = 0
      do k = start(keys(1, f)), start(keys(1, f) + 1) - 1
        g = bucket(k)
        if (.not. all(keys(:, g) == keys(:, f))) cycle
        matches = matches + 1
        if (g /= f) other(f) = g
      end do
      exterior(f) = matches == 1
      if (matches /= 2) other(f) = 0        ! (a face of 3 elements: not a body's inside)
    end do
    with_interior = .false.
    if (present(interior)) with_interior = interior
    if (.not. with_interior) other = 0
    ! facets in element order: exterior faces oriented outward, 3D shells as given
    call allocate_facets(surface, count(exterior) + nshell + count(other > 0))
    nout = 0
    f = 0
    do e = 1, model%elements%n
      if (.not. selected(model%elements%part(e))) cycle
      if (model%dimension == 3 .and. model%elements%keyword(e) == ELEM_SHELL) then
        nout = nout + 1
        n = NODES_OF_TOPO(model%elements%topology(e))
        surface%facets(:, nout) = 0
        surface%facets(1:n, nout) = model%elements%conn(1:n, e)
        surface%nvertex(nout) = n
        surface%element(nout) = e
        surface%outward(nout) = .false.
        cycle
      end if
      do while (f < nfaces)
        if (face_elem(f + 1) /= e) exit
        f = f + 1
        if (.not. exterior(f)) cycle
        nout = nout + 1
        surface%facets(:, nout) = face_nodes(:, f)
        surface%nvertex(nout) = face_nv(f)
        surface%element(nout) = e
        surface%outward(nout) = .true.
        call orient_outward(model, e, surface%facets(:, nout), face_nv(f))
      end do
    end do
    ! eroding contacts: the faces inside, each element's in element order, out of it
    do f = 1, nfaces
      if (other(f) == 0) cycle
      nout = nout + 1
      surface%facets(:, nout) = face_nodes(:, f)
      surface%nvertex(nout) = face_nv(f)
      surface%element(nout) = face_elem(f)
      surface%neighbour(nout) = face_elem(other(f))
      surface%outward(nout) = .true.
      call orient_outward(model, face_elem(f), surface%facets(:, nout), face_nv(f))
    end do
    surface%nfacet = nout
  end subroutine contact_parts_to_facets

  !> Keep the facets whose vertices are all among the given nodes (a node set's members),
  !> in their order.
  subroutine keep_facets_of_nodes(model, members, surface)
    type(model_t), intent(in) :: model                  !< the model
    integer, intent(in) :: members(:)                   !< node indices
    type(contact_surface_t), intent(inout) :: surface   !< facets kept in place
    logical, allocatable :: member(:)
    integer :: f, n
    allocate(member(model%nodes%n))
    member = .false.
    member(pack(members, members >= 1 .and. members <= model%nodes%n)) = .true.
    n = 0
    do f = 1, surface%nfacet
      if (.not. all(member(surface%facets(1:surface%nvertex(f), f)))) cycle
      n = n + 1
      surface%facets(:, n) = surface%facets(:, f)
      surface%nvertex(n) = surface%nvertex(f)
      surface%element(n) = surface%element(f)
      surface%outward(n) = surface%outward(f)
      surface%neighbour(n) = surface%neighbour(f)
    end do
    surface%nfacet = n
  end subroutine keep_facets_of_nodes

  !> Reverse a facet (a 2D edge: swap its ends; else keep the first vertex and reverse the
  !> others) when its normal points towards the centroid of element e (reference coordinates).
  subroutine orient_outward(model, e, facet, nv)
    type(model_t), intent(in) :: model        !< the model
    integer, intent(in) :: e                  !< the element the facet bounds
    integer, intent(inout) :: facet(4)        !< facet nodes
    integer, intent(in) :: nv                 !< vertices used
    real(wp) :: xv(3, MAX_VERTICES), centre(3), element_centre(3)
    integer :: i, nn
    xv = 0.0_wp
    do i = 1, nv
      xv(1:model%dimension, i) = model%nodes%x(1:model%dimension, facet(i))
    end do
    centre = sum(xv(:, 1:nv), dim=2)/nv
    nn = NODES_OF_TOPO(model%elements%topology(e))
    element_centre = 0.0_wp
    do i = 1, nn
      element_centre(1:model%dimension) = element_centre(1:model%dimension) + &
          model%nodes%x(1:model%dimension, model%elements%conn(i, e))
    end do
    element_centre = element_centre/nn
    if (dot_product(area_vector(nv, xv), centre - element_centre) >= 0.0_wp) return
    if (nv == 2) then
      facet(1:2) = facet(2:1:-1)
    else
      facet(2:nv) = facet(nv:2:-1)
    end if
  end subroutine orient_outward

  !> Distinct surface nodes (ascending) and each facet's positions in that list.
  subroutine number_nodes(nnodes, surface)
    integer, intent(in) :: nnodes                       !< mesh nodes
    type(contact_surface_t), intent(inout) :: surface   !< facets given; nodes, local set
    integer, allocatable :: position(:)
    integer :: f, i, n
    allocate(position(nnodes))
    position = 0
    do f = 1, surface%nfacet
      position(surface%facets(1:surface%nvertex(f), f)) = 1
    end do
    surface%nnode = count(position > 0)
    allocate(surface%nodes(surface%nnode))
    i = 0
    do n = 1, nnodes
      if (position(n) == 0) cycle
      i = i + 1
      surface%nodes(i) = n
      position(n) = i
    end do
    allocate(surface%local(4, surface%nfacet))
    surface%local = 0
    do f = 1, surface%nfacet
      do i = 1, surface%nvertex(f)
        surface%local(i, f) = position(surface%facets(i, f))
      end do
    end do
  end subroutine number_nodes

  !> Facet arrays for up to n facets (none used yet).
  subroutine allocate_facets(surface, n)
    type(contact_surface_t), intent(inout) :: surface   !< the surface
    integer, intent(in) :: n                            !< room
    allocate(surface%facets(4, n), surface%nvertex(n), surface%element(n), surface%outward(n), &
             surface%neighbour(n))
    surface%facets = 0
    surface%nvertex = 0
    surface%element = 0
    surface%neighbour = 0
    surface%outward = .false.
    surface%nfacet = 0
  end subroutine allocate_facets

  !> Node indices sorted ascending, padded with zeros to 4 entries.
  pure function sorted_key(nodes) result(key)
    integer, intent(in) :: nodes(:)   !< 2 to 4 node indices
    integer :: key(4)
    integer :: i, j, t
    key = 0
    key(1:size(nodes)) = nodes
    do i = 2, size(nodes)
      t = key(i)
      j = i - 1
      do while (j >= 1)
        if (key(j) <= t) exit
        key(j + 1) = key(j)
        j = j - 1
      end do
      key(j + 1) = t
    end do
  end function sorted_key

  !> True when index s is a set of the given kind.
  logical function valid_set(model, s, kind)
    type(model_t), intent(in) :: model   !< the model
    integer, intent(in) :: s, kind       !< set index, SET_* kind
    valid_set = .false.
    if (s < 1 .or. s > model%n_sets) return
    valid_set = model%sets(s)%kind == kind .and. allocated(model%sets(s)%members)
  end function valid_set

  !> 'segment set 3', 'part 7' or 'part set 2' (user ids) for messages.
  function target_name(model, kind, target) result(s)
    type(model_t), intent(in) :: model   !< the model
    integer, intent(in) :: kind, target  !< SURFACE_* code and index
    character(len=:), allocatable :: s
    select case (kind)
    case (SURFACE_PART)
      s = 'part '//itoa(model%parts(target)%id)
    case (SURFACE_PART_SET)
      s = 'part set '//itoa(model%sets(target)%id)
    case (SURFACE_NODE_SET)
      s = 'node set '//itoa(model%sets(target)%id)
    case (SURFACE_ALL_PARTS)
      s = 'all parts'
    case (SURFACE_ALL_BUT_SET)
      s = 'all parts but those of part set '//itoa(model%sets(target)%id)
    case default
      s = 'segment set '//itoa(model%sets(target)%id)
    end select
  end function target_name

  !> Record a failure.
  subroutine fail(status, message)
    type(status_t), intent(inout) :: status   !< the status
    character(len=*), intent(in) :: message   !< what failed
    status%ok = .false.
    status%message = message
  end subroutine fail

  ! ====================================================================== search

  !> Candidate pairs: pairs(1:2, 1:npairs) = (slave facet, master facet) for every pair whose
  !> slave bounding box overlaps the master bounding box enlarged by margin on every side,
  !> without duplicates, sorted by slave facet then master facet. x holds the current
  !> coordinates, x(3, nnodes) (rows 1:dim used; in 2D z is ignored). The master boxes are
  !> binned into a uniform grid of cells of about the mean master facet size; each slave box
  !> visits the cells it overlaps. search keeps the grid; its arrays and pairs are reallocated
  !> only when they must grow.
  subroutine contact_search_build(search, slave, master, x, margin, pairs, npairs, slave_out, &
                                  master_out)
    type(contact_search_t), intent(inout) :: search   !< grid, kept between calls
    type(contact_surface_t), intent(in) :: slave      !< slave surface
    type(contact_surface_t), intent(in) :: master     !< master surface
    real(wp), intent(in) :: x(:,:)                    !< (3, nnodes) current coordinates
    real(wp), intent(in) :: margin                    !< box enlargement (length, >= 0)
    integer, allocatable, intent(inout) :: pairs(:,:) !< (2, capacity) candidate pairs
    integer, intent(out) :: npairs                    !< pairs found
    logical, intent(in), optional :: slave_out(:)     !< (slave facets) left out (eroded,
                                                      !< or inside the body)
    logical, intent(in), optional :: master_out(:)    !< (master facets) left out
    integer :: dim, nm, s, m, c, k, nfound, i0(3), i1(3), i, j, l
    real(wp) :: slo(3), shi(3)
    logical :: hit
    npairs = 0
    search%n_box_tests = 0
    dim = slave%dim
    search%dim = dim
    nm = master%nfacet
    if (.not. allocated(pairs)) then
      allocate(pairs(2, max(64, 4*slave%nfacet)))
      search%n_grows = search%n_grows + 1
    end if
    if (nm == 0 .or. slave%nfacet == 0) return
    call ensure_real2(search%lo, nm, search%n_grows)
    call ensure_real2(search%hi, nm, search%n_grows)
    call ensure_int(search%stamp, nm, search%n_grows)
    call ensure_int(search%found, nm, search%n_grows)
    do m = 1, nm
      call facet_box(master, m, x, dim, search%lo(:, m), search%hi(:, m))
    end do
    call build_grid(search, nm, margin)
    search%stamp(1:nm) = 0
    do s = 1, slave%nfacet
      if (present(slave_out)) then
        if (slave_out(s)) cycle
      end if
      call facet_box(slave, s, x, dim, slo, shi)
      call cell_range(search, slo, shi, i0, i1, hit)
      if (.not. hit) cycle
      nfound = 0
      do l = i0(3), i1(3)
        do j = i0(2), i1(2)
          do i = i0(1), i1(1)
            c = 1 + i + search%ncell(1)*(j + search%ncell(2)*l)
            do k = search%cell_start(c), search%cell_start(c + 1) - 1
              m = search%cell_master(k)
              if (search%stamp(m) == s) cycle
              search%stamp(m) = s
              if (present(master_out)) then
                if (master_out(m)) cycle
              end if
              search%n_box_tests = search%n_box_tests + 1
              if (any(slo(1:dim) > search%hi(1:dim, m)) .or. &
                  any(shi(1:dim) < search%lo(1:dim, m))) cycle
              nfound = nfound + 1
              search%found(nfound) = m
            end do
          end do
        end do
      end do
      if (nfound == 0) cycle
      call sort_ints(search%found(1:nfound))
      if (npairs + nfound > size(pairs, 2)) then
        call grow_pairs(pairs, npairs, npairs + nfound)
        search%n_grows = search%n_grows + 1
      end if
      pairs(1, npairs+1:npairs+nfound) = s
      pairs(2, npairs+1:npairs+nfound) = search%found(1:nfound)
      npairs = npairs + nfound
    end do
  end subroutine contact_search_build

  !> Bounding box of facet f over the first dim coordinates (others 0).
  pure subroutine facet_box(surface, f, x, dim, lo, hi)
    type(contact_surface_t), intent(in) :: surface   !< the surface
    integer, intent(in) :: f, dim                    !< facet, dimensions
    real(wp), intent(in) :: x(:,:)                   !< coordinates
    real(wp), intent(out) :: lo(3), hi(3)            !< box
    integer :: i, n
    lo = 0.0_wp
    hi = 0.0_wp
    n = surface%facets(1, f)
    lo(1:dim) = x(1:dim, n)
    hi(1:dim) = x(1:dim, n)
    do i = 2, surface%nvertex(f)
      n = surface%facets(i, f)
      lo(1:dim) = min(lo(1:dim), x(1:dim, n))
      hi(1:dim) = max(hi(1:dim), x(1:dim, n))
    end do
  end subroutine facet_box

  !> Cell size from the mean master box (before the margin; at least the margin), enlarge the
  !> boxes by the margin, the grid over their union, and the masters binned by a counting sort
  !> (ascending per cell).
  subroutine build_grid(search, nm, margin)
    type(contact_search_t), intent(inout) :: search   !< lo, hi given (plain boxes)
    integer, intent(in) :: nm                         !< master facets
    real(wp), intent(in) :: margin                    !< box enlargement
    real(wp) :: h, extent(3), cells, limit, glo(3), ghi(3)
    integer :: dim, m, c, i, j, l, i0(3), i1(3), ncells, nentries
    integer(i8) :: entries
    dim = search%dim
    h = 0.0_wp
    do m = 1, nm
      h = h + maxval(search%hi(1:dim, m) - search%lo(1:dim, m))
    end do
    ! a margin larger than the facets would put each master in many cells: cells >= margin
    h = max(h/nm, margin)
    search%lo(1:dim, 1:nm) = search%lo(1:dim, 1:nm) - margin
    search%hi(1:dim, 1:nm) = search%hi(1:dim, 1:nm) + margin
    search%lo(dim+1:3, 1:nm) = 0.0_wp
    search%hi(dim+1:3, 1:nm) = 0.0_wp
    glo = minval(search%lo(:, 1:nm), dim=2)
    ghi = maxval(search%hi(:, 1:nm), dim=2)
    extent = ghi - glo
    if (h <= 0.0_wp) h = maxval(extent)
    if (h <= 0.0_wp) h = 1.0_wp                 ! all masters in one point: one cell
    ! cap the number of cells: widen them when the box is large against the facets
    limit = real(MAX_CELLS_PER_FACET, wp)*nm
    cells = product(max(1.0_wp, extent(1:dim)/h))
    if (cells > limit) h = h*(cells/limit)**(1.0_wp/dim)
    search%ncell = 1
    do      ! rounding up per direction may still exceed the cap: widen a little more
      search%ncell(1:dim) = max(1, ceiling(extent(1:dim)/h))
      if (product(real(search%ncell, wp)) <= limit) exit
      h = h*CELL_WIDENING
    end do
    search%cell_size = h
    search%origin = glo
    ncells = product(search%ncell)
    call ensure_int(search%cell_start, ncells + 1, search%n_grows)
    ! count, prefix sum, fill
    search%cell_start(1:ncells+1) = 0
    entries = 0
    do m = 1, nm
      call master_cells(search, m, i0, i1)
      entries = entries + product(int(i1 - i0 + 1, i8))
      do l = i0(3), i1(3)
        do j = i0(2), i1(2)
          do i = i0(1), i1(1)
            c = 1 + i + search%ncell(1)*(j + search%ncell(2)*l)
            search%cell_start(c + 1) = search%cell_start(c + 1) + 1
          end do
        end do
      end do
    end do
    nentries = int(entries)
    search%cell_start(1) = 1
    do c = 1, ncells
      search%cell_start(c + 1) = search%cell_start(c + 1) + search%cell_start(c)
    end do
    call ensure_int(search%cell_master, nentries, search%n_grows)
    do m = 1, nm
      call master_cells(search, m, i0, i1)
      do l = i0(3), i1(3)
        do j = i0(2), i1(2)
          do i = i0(1), i1(1)
            c = 1 + i + search%ncell(1)*(j + search%ncell(2)*l)
            search%cell_master(search%cell_start(c)) = m
            search%cell_start(c) = search%cell_start(c) + 1
          end do
        end do
      end do
    end do
    do c = ncells, 1, -1
      search%cell_start(c + 1) = search%cell_start(c)
    end do
    search%cell_start(1) = 1
  end subroutine build_grid

  !> Cells (0-based per direction) covered by the enlarged box of master m.
  pure subroutine master_cells(search, m, i0, i1)
    type(contact_search_t), intent(in) :: search   !< the grid
    integer, intent(in) :: m                       !< master facet
    integer, intent(out) :: i0(3), i1(3)           !< first and last cells
    integer :: d
    i0 = 0
    i1 = 0
    do d = 1, search%dim
      i0(d) = cell_of(search, d, search%lo(d, m))
      i1(d) = cell_of(search, d, search%hi(d, m))
    end do
  end subroutine master_cells

  !> Cell (0-based) holding coordinate v in direction d, clipped to the grid.
  pure integer function cell_of(search, d, v)
    type(contact_search_t), intent(in) :: search   !< the grid
    integer, intent(in) :: d                       !< direction
    real(wp), intent(in) :: v                      !< coordinate
    real(wp) :: t
    t = (v - search%origin(d))/search%cell_size
    t = max(0.0_wp, min(t, real(search%ncell(d) - 1, wp)))
    cell_of = int(t)
  end function cell_of

  !> Cells a slave box overlaps; hit = false when it misses the grid.
  pure subroutine cell_range(search, lo, hi, i0, i1, hit)
    type(contact_search_t), intent(in) :: search   !< the grid
    real(wp), intent(in) :: lo(3), hi(3)           !< slave box
    integer, intent(out) :: i0(3), i1(3)           !< first and last cells
    logical, intent(out) :: hit                    !< the box meets the grid
    integer :: d
    real(wp) :: top
    i0 = 0
    i1 = 0
    hit = .false.
    do d = 1, search%dim
      top = search%origin(d) + search%ncell(d)*search%cell_size
      if (hi(d) < search%origin(d) .or. lo(d) > top) return
      i0(d) = cell_of(search, d, lo(d))
      i1(d) = cell_of(search, d, hi(d))
    end do
    hit = .true.
  end subroutine cell_range

  !> Sort a short integer list ascending (insertion sort; heapsort when long).
  pure subroutine sort_ints(a)
    integer, intent(inout) :: a(:)   !< the list
    integer :: i, j, t, n
    n = size(a)
    if (n > INSERTION_SORT_MAX) then
      call heap_sort(a)
      return
    end if
    do i = 2, n
      t = a(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= t) exit
        a(j + 1) = a(j)
        j = j - 1
      end do
      a(j + 1) = t
    end do
  end subroutine sort_ints

  !> Heapsort, ascending.
  pure subroutine heap_sort(a)
    integer, intent(inout) :: a(:)   !< the list
    integer :: n, i, t
    n = size(a)
    do i = n/2, 1, -1
      call sift_down(a, i, n)
    end do
    do i = n, 2, -1
      t = a(1)
      a(1) = a(i)
      a(i) = t
      call sift_down(a, 1, i - 1)
    end do
  end subroutine heap_sort

  !> Restore the max-heap below position i within a(1:n).
  pure subroutine sift_down(a, i, n)
    integer, intent(inout) :: a(:)   !< the heap
    integer, intent(in) :: i, n      !< root and heap size
    integer :: parent, child, t
    parent = i
    t = a(parent)
    do
      child = 2*parent
      if (child > n) exit
      if (child < n) then
        if (a(child + 1) > a(child)) child = child + 1
      end if
      if (a(child) <= t) exit
      a(parent) = a(child)
      parent = child
    end do
    a(parent) = t
  end subroutine sift_down

  !> Make an integer work array hold at least n entries (grown by GROWTH, counted).
  subroutine ensure_int(a, n, n_grows)
    integer, allocatable, intent(inout) :: a(:)   !< the array (contents not kept)
    integer, intent(in) :: n                      !< entries needed
    integer, intent(inout) :: n_grows             !< reallocation counter
    integer :: room
    if (allocated(a)) then
      if (size(a) >= n) return
      room = max(n, int(GROWTH*size(a)))
      deallocate(a)
    else
      room = n
    end if
    allocate(a(room))
    n_grows = n_grows + 1
  end subroutine ensure_int

  !> Make a (3, :) real work array hold at least n columns (grown by GROWTH, counted).
  subroutine ensure_real2(a, n, n_grows)
    real(wp), allocatable, intent(inout) :: a(:,:)   !< the array (contents not kept)
    integer, intent(in) :: n                         !< columns needed
    integer, intent(inout) :: n_grows                !< reallocation counter
    integer :: room
    if (allocated(a)) then
      if (size(a, 2) >= n) return
      room = max(n, int(GROWTH*size(a, 2)))
      deallocate(a)
    else
      room = n
    end if
    allocate(a(3, room))
    n_grows = n_grows + 1
  end subroutine ensure_real2

  !> Grow the pair list to hold at least n pairs, keeping the first npairs.
  subroutine grow_pairs(pairs, npairs, n)
    integer, allocatable, intent(inout) :: pairs(:,:)   !< the list
    integer, intent(in) :: npairs, n                    !< pairs kept, pairs needed
    integer, allocatable :: grown(:,:)
    allocate(grown(2, max(n, 2*size(pairs, 2))))
    grown(:, 1:npairs) = pairs(:, 1:npairs)
    call move_alloc(grown, pairs)
  end subroutine grow_pairs

end module mefem_contact_surfaces
