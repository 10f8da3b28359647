!> The model as read from the deck: mesh, parts, sections, materials, sets, curves,
!> boundary conditions, loads, contacts and controls.
!>
!> Entities are stored in flat arrays in deck order with their user ids. References between
!> entities (element to node, part to section, BC to curve ...) are read as ids and resolved
!> to 1-based indices by model_resolve (src/model/model_resolve.f90), which also reports
!> every dangling reference. Each record keeps where it was read (file index, line number)
!> for messages. Units are those of the deck (a consistent set; mefem converts nothing).
module mefem_model
  use mefem_kinds, only: wp
  use mefem_output_mesh, only: TOPO_TRI3, TOPO_QUAD4, TOPO_TET4, TOPO_PENTA6, TOPO_HEX8
  implicit none
  private

  public :: box_holds

  public :: TOPO_TRI3, TOPO_QUAD4, TOPO_TET4, TOPO_PENTA6, TOPO_HEX8

  ! element source keyword
  integer, parameter, public :: ELEM_SOLID = 1, ELEM_SHELL = 2
  ! section kinds
  integer, parameter, public :: SECTION_SOLID = 1, SECTION_SHELL = 2
  ! material kinds
  integer, parameter, public :: MAT_ELASTIC = 1, MAT_PIECEWISE_LINEAR = 24, MAT_POWER_LAW = 18, &
                                MAT_RIGID = 20, MAT_MOONEY_RIVLIN = 27, MAT_PLASTIC_KINEMATIC = 3, &
                                MAT_JOHNSON_COOK = 15, MAT_SIMPLIFIED_JOHNSON_COOK = 98
  ! targets of boundary conditions and loads
  integer, parameter, public :: ON_NODE = 1, ON_NODE_SET = 2, ON_PART = 3, ON_ALL_NODES = 4, &
                                ON_PART_SET = 5, ON_SEGMENT_SET = 6
  ! sets
  !> VAD of *BOUNDARY_PRESCRIBED_MOTION: what the curve gives
  integer, parameter, public :: VAD_VELOCITY = 0, VAD_ACCELERATION = 1, VAD_DISPLACEMENT = 2
  integer, parameter, public :: SET_NODE = 1, SET_SEGMENT = 2, SET_PART = 3, SET_SOLID = 4, &
                                SET_SHELL = 5, SET_KINDS = 5
  ! entries of *SET_NODE_GENERAL (negative: the D- options, which remove)
  !> TC code of *NODE and *CONSTRAINED_GLOBAL -> fixed x, y, z (1 x, 2 y, 3 z, 4 xy, 5 yz,
  !> 6 zx, 7 xyz).
  logical, parameter, public :: TC_FIXED(3, 0:7) = reshape([ &
      .false., .false., .false.,  .true., .false., .false.,  .false., .true., .false., &
      .false., .false., .true.,   .true., .true., .false.,   .false., .true., .true., &
      .true., .false., .true.,    .true., .true., .true.], [3, 8])
  !> Failure criteria of *MAT_ADD_EROSION, in the order of erosion_limit: pressure above MXPRES
  !> or below MNPRES, minimum principal strain below MNEPS, effective strain above EFFEPS,
  !> volumetric strain beyond VOLEPS (its sign the side), maximum principal stress above
  !> SIGP1, equivalent stress above SIGVM, maximum principal strain above MXEPS, time after
  !> FAILTM.
  integer, parameter, public :: EROSION_MXPRES = 1, EROSION_MNEPS = 2, EROSION_EFFEPS = 3, &
      EROSION_VOLEPS = 4, EROSION_MNPRES = 5, EROSION_SIGP1 = 6, EROSION_SIGVM = 7, &
      EROSION_MXEPS = 8, EROSION_FAILTM = 9, EROSION_CRITERIA = 9
  integer, parameter, public :: GENERAL_ALL = 1, GENERAL_NODE = 2, GENERAL_PART = 3, &
                                GENERAL_SET = 4, GENERAL_BOX = 5, GENERAL_SEG = 6
  !> a contact's FS of -1: the friction (FS, FD, DC) of its SURFA parts' *PART_CONTACT
  real(wp), parameter, public :: FS_FROM_PARTS = -1.0_wp

  !> Where a record was read.
  type, public :: source_t
    integer :: file = 0   !< file index (mefem_deck_source file_name)
    integer :: line = 0   !< line number
  end type source_t

  !> All nodes.
  type, public :: nodes_t
    integer :: n = 0
    integer, allocatable :: id(:)           !< (n) user ids
    real(wp), allocatable :: x(:,:)         !< (3,n) coordinates
    integer, allocatable :: tc(:), rc(:)    !< (n) translational/rotational constraint codes
    type(source_t), allocatable :: src(:)   !< (n)
    real(wp), allocatable :: added_mass(:)  !< (n) mass of *ELEMENT_MASS(_PART) (after
                                            !< resolve; zero where none)
  end type nodes_t

  !> All elements, solids and shells alike (up to 8 corner nodes).
  type, public :: elements_t
    integer :: n = 0
    integer, allocatable :: id(:)           !< (n) user ids
    integer, allocatable :: part_id(:)      !< (n) user part id
    integer, allocatable :: part(:)         !< (n) part index (after resolve)
    integer, allocatable :: keyword(:)      !< (n) ELEM_SOLID or ELEM_SHELL
    integer, allocatable :: topology(:)     !< (n) TOPO_* code (after resolve)
    integer, allocatable :: node_ids(:,:)   !< (8,n) user node ids as read (0 = none)
    integer, allocatable :: conn(:,:)       !< (8,n) node indices (after resolve; 0 = none)
    type(source_t), allocatable :: src(:)   !< (n)
  end type elements_t

  !> *PART.
  type, public :: part_t
    integer :: id = 0
    character(len=80) :: title = ''
    integer :: section_id = 0, material_id = 0, eos_id = 0, hourglass_id = 0
    integer :: section = 0, material = 0    !< indices (after resolve)
    integer :: hourglass = 0                !< index of its *HOURGLASS (after resolve; 0: none)
    logical :: has_contact = .false.        !< *PART_CONTACT gave the card below
    real(wp) :: contact_fs = 0.0_wp, contact_fd = 0.0_wp   !< *PART_CONTACT FS FD (used by
                                            !< the contacts whose FS is -1)
    real(wp) :: contact_dc = 0.0_wp         !< *PART_CONTACT DC
    logical :: has_inertia = .false.        !< *PART_INERTIA gave the cards below (rigid parts)
    real(wp) :: inertia_centre(3) = 0.0_wp  !< XC YC ZC: centre of mass
    integer :: inertia_node_id = 0          !< NODEID: the centre is this node (0: XC YC ZC)
    integer :: inertia_node = 0             !< its index (after resolve)
    real(wp) :: inertia_mass = 0.0_wp       !< TM: the body's mass
    real(wp) :: inertia_tensor(6) = 0.0_wp  !< IXX IXY IXZ IYY IYZ IZZ about the centre,
                                            !< global axes
    real(wp) :: inertia_velocity(6) = 0.0_wp  !< VTX VTY VTZ VRX VRY VRZ: initial velocity
                                              !< of the centre and angular velocity
    type(source_t) :: inertia_src           !< where card 3 was read
    type(source_t) :: src
  end type part_t

  !> *HOURGLASS: the hourglass control of the parts that name its HGID.
  type, public :: hourglass_t
    integer :: id = 0                       !< HGID
    integer :: ihq = 0                      !< IHQ (0: *CONTROL_HOURGLASS's)
    real(wp) :: qm = 0.0_wp                 !< QM (0: the default, 0.1)
    type(source_t) :: src
  end type hourglass_t

  !> *SECTION_SOLID / *SECTION_SHELL.
  type, public :: section_t
    integer :: id = 0
    integer :: kind = SECTION_SOLID
    integer :: elform = 1
    integer :: aet = 0
    real(wp) :: thickness(4) = 0.0_wp       !< shells: T1..T4
    real(wp) :: shear_factor = 1.0_wp       !< shells: SHRF
    integer :: nip = 2                      !< shells: integration points through thickness
    type(source_t) :: src
  end type section_t

  !> Spall models of *MAT_JOHNSON_COOK (material_t%spall; SPALL 1, 2, 3 of the deck).
  integer, parameter, public :: SPALL_NONE = 0, SPALL_PRESSURE_CUTOFF = 1, SPALL_PRINCIPAL = 2, &
                                SPALL_HYDROSTATIC = 3

  !> A material card; the fields used depend on kind.
  type, public :: material_t
    integer :: id = 0
    integer :: kind = 0
    character(len=80) :: title = ''
    real(wp) :: density = 0.0_wp            !< RO
    real(wp) :: young = 0.0_wp              !< E
    real(wp) :: poisson = 0.0_wp            !< PR
    ! plasticity (MAT_024, MAT_018, MAT_003)
    real(wp) :: yield_stress = 0.0_wp       !< SIGY
    real(wp) :: tangent_modulus = 0.0_wp    !< ETAN
    real(wp) :: beta = 0.0_wp               !< BETA (MAT_003): 0 kinematic, 1 isotropic hardening
    real(wp) :: failure_strain = 0.0_wp     !< effective plastic strain at which a point fails
                                            !< (explicit: erosion): FAIL (MAT_024), EPSF
                                            !< (MAT_018), FS (MAT_003), PSFAIL (MAT_098);
                                            !< 0: none
    logical :: add_erosion = .false.        !< *MAT_ADD_EROSION criteria (below) apply
    real(wp) :: erosion_limit(EROSION_CRITERIA) = 0.0_wp  !< their limits (EROSION_*)
    logical :: erosion_used(EROSION_CRITERIA) = .false.   !< which criteria are used
    integer :: erosion_conditions = 1       !< NCS: criteria met at once for failure
    real(wp) :: cowper_c = 0.0_wp, cowper_p = 0.0_wp   !< C, P (MAT_024) / SRC, SRP (MAT_018)
    integer :: lcss = 0                     !< curve id of stress vs plastic strain (MAT_024)
    integer :: lcss_curve = 0               !< its index (after resolve; a table: its
                                            !< first, lowest-rate curve)
    integer :: lcss_table = 0               !< LCSS a *DEFINE_TABLE of curves by strain rate:
                                            !< its index in the curves (after resolve)
    logical :: lcss_log_rates = .false.     !< the table's values are ln(rate) (first < 0)
    integer :: lcss_upper = 0               !< (one update) the next rate's curve and its
    real(wp) :: lcss_weight = 0.0_wp        !< weight in the blend with lcss_curve
    integer :: lcsr = 0                     !< strain-rate curve id (MAT_024)
    integer :: lcsr_curve = 0               !< its index (after resolve)
    real(wp) :: vp = 0.0_wp                 !< VP rate formulation flag
    real(wp) :: vp_alpha_old = 0.0_wp       !< (one update, VP = 1) alpha_n and the step dt:
    real(wp) :: vp_dt = 0.0_wp              !< the plastic rate (alpha - alpha_n)/dt scales K
    integer :: n_points = 0                 !< EPS/ES pairs given (MAT_024)
    real(wp) :: eps(8) = 0.0_wp, es(8) = 0.0_wp
    real(wp) :: k_strength = 0.0_wp         !< K (MAT_018)
    real(wp) :: n_exponent = 0.0_wp         !< N (MAT_018, MAT_015, MAT_098)
    ! Johnson-Cook (MAT_015, MAT_098): (A + B alpha^N)(1 + C ln(rate/EPSO))(1 - T*^M)
    real(wp) :: jc_a = 0.0_wp, jc_b = 0.0_wp, jc_c = 0.0_wp   !< A, B, C
    real(wp) :: jc_m = 0.0_wp               !< M (MAT_015)
    real(wp) :: melt_temperature = 0.0_wp   !< TM (MAT_015)
    real(wp) :: room_temperature = 0.0_wp   !< TR (MAT_015)
    real(wp) :: reference_rate = 1.0_wp     !< EPSO
    real(wp) :: heat_capacity = 0.0_wp      !< CP (MAT_015; 0: no heating)
    real(wp) :: max_stress = 0.0_wp         !< SIGMAX (MAT_098; 0: no cap)
    ! Johnson-Cook failure (MAT_015): eps_f = [D1 + D2 exp(D3 s*)][1 + D4 ln r*][1 + D5 T*]
    logical :: jc_fails = .false.           !< D1 or D2 given: damage accumulates (erosion)
    real(wp) :: jc_damage(5) = 0.0_wp       !< D1 .. D5
    real(wp) :: jc_min_failure_strain = 0.0_wp   !< EFMIN: the least eps_f
    logical :: jc_keep_failed = .false.     !< EROD /= 0: a failed point is not eroded; it
                                            !< keeps its pressure, no deviatoric stress
    ! spall (MAT_015 PC, SPALL; explicit): SPALL_NONE, SPALL_PRESSURE_CUTOFF (p >= PC),
    ! SPALL_PRINCIPAL (spalls when sigma_max >= -PC), SPALL_HYDROSTATIC (spalls when p < PC);
    ! a spalled point carries compression only, no deviatoric stress
    integer :: spall = SPALL_NONE
    real(wp) :: pressure_cutoff = 0.0_wp    !< PC (< 0: a tensile pressure)
    ! Mooney-Rivlin (MAT_027)
    real(wp) :: mr_a = 0.0_wp, mr_b = 0.0_wp
    ! rigid (MAT_020)
    integer :: cmo = 0, con1 = 0, con2 = 0
    type(source_t) :: src
  end type material_t

  !> *SET_NODE / *SET_PART / *SET_SEGMENT: members as user ids, resolved to indices.
  type, public :: set_t
    integer :: id = 0
    integer :: kind = SET_NODE
    character(len=80) :: title = ''
    integer :: n = 0
    integer, allocatable :: member_ids(:)   !< (n) node or part ids; segments: (4*n) node ids;
                                            !< generated sets: (2*n) ranges B E until
                                            !< resolved, then the (n) ids of their nodes
    integer, allocatable :: members(:)      !< indices (after resolve)
    logical :: general = .false.            !< *SET_NODE_GENERAL: member_ids holds its entries
                                            !< (code, count, ids...; GENERAL_* codes) until
                                            !< resolved
    logical :: generated = .false.          !< from _GENERATE ranges: ids in a range that no
                                            !< node has are left out (as LS-DYNA does)
    type(source_t) :: src
  end type set_t

  !> *DEFINE_CURVE with its scale factors and offsets already applied.
  !> *DEFINE_CURVE (or _SMOOTH), or a *DEFINE_TABLE (is_table: one curve per value, ids
  !> shared with the curves as in LS-DYNA).
  type, public :: curve_t
    integer :: id = 0
    character(len=80) :: title = ''
    integer :: sidr = 0
    integer :: n = 0
    real(wp), allocatable :: t(:), f(:)     !< abscissas and ordinates (table: f unused)
    type(source_t) :: src
    logical :: is_table = .false.           !< a *DEFINE_TABLE: t holds its values
    integer, allocatable :: member_ids(:)   !< table: curve id per value (0: the k-th curve
                                            !< that follows the table in the deck)
    integer, allocatable :: members(:)      !< table: their curve indices (after resolve)
    integer :: follows = 0                  !< table: index of the curve defined after it
  end type curve_t

  !> *BOUNDARY_SPC_NODE/_SET: fixed degrees of freedom.
  type, public :: spc_t
    integer :: target_kind = ON_NODE
    integer :: target_id = 0, target = 0     !< id and index of node or node set
    integer :: cid = 0
    logical :: dof(6) = .false.              !< x y z rx ry rz fixed (after resolve: global
                                             !< axes; with CID those local axes that are
                                             !< global ones)
    integer :: n_skew = 0                    !< (resolve) fixed local axes that are not
    real(wp) :: skew(3, 3) = 0.0_wp          !< global axes: their directions (columns)
    integer :: skew_axis(3) = 0              !< (resolve) their local axes (1 x, 2 y, 3 z)
    integer :: moving_system = 0             !< (resolve) CID's index when it moves (FLAG 1):
                                             !< every fixed local axis is then skew
    real(wp) :: birth = 0.0_wp, death = 1.0e20_wp
    type(source_t) :: src
  end type spc_t

  !> *BOUNDARY_PRESCRIBED_MOTION_NODE/_SET/_RIGID.
  type, public :: prescribed_motion_t
    integer :: target_kind = ON_NODE
    integer :: target_id = 0, target = 0
    integer :: dof = 0, vad = 0
    integer :: curve_id = 0, curve = 0
    real(wp) :: scale = 1.0_wp
    integer :: vector_id = 0
    real(wp) :: direction(3) = 0.0_wp        !< (resolve) DOF 4, 8: the unit vector of VID
    real(wp) :: death = 1.0e28_wp, birth = 0.0_wp
    type(source_t) :: src
  end type prescribed_motion_t

  !> *LOAD_NODE_POINT/_SET: nodal force (or moment) from a curve.
  type, public :: nodal_load_t
    integer :: target_kind = ON_NODE
    integer :: target_id = 0, target = 0
    integer :: dof = 0
    integer :: curve_id = 0, curve = 0
    real(wp) :: scale = 1.0_wp
    integer :: cid = 0
    real(wp) :: direction(3) = 0.0_wp        !< (resolve) CID: the local axis DOF, global
    type(source_t) :: src
  end type nodal_load_t

  !> *LOAD_SEGMENT(_SET): pressure on a segment or on every segment of a set.
  type, public :: pressure_load_t
    integer :: curve_id = 0, curve = 0
    real(wp) :: scale = 1.0_wp
    real(wp) :: arrival = 0.0_wp
    integer :: set_id = 0, set = 0           !< segment set (for _SET), else 0
    integer :: node_ids(4) = 0, nodes(4) = 0 !< single segment
    type(source_t) :: src
  end type pressure_load_t

  !> *LOAD_BODY_X/_Y/_Z: a base acceleration a(t) = SF curve(t) along a global axis; the
  !> body force on a node of mass m is -m a (gravity along -z: *LOAD_BODY_Z with SF curve = g).
  type, public :: body_load_t
    integer :: direction = 0                 !< 1 x, 2 y, 3 z
    integer :: curve_id = 0, curve = 0       !< LCID and its index (after resolve)
    real(wp) :: scale = 1.0_wp               !< SF
    integer :: dr_curve_id = 0               !< LCIDDR (dynamic relaxation: not used)
    real(wp) :: centre(3) = 0.0_wp           !< XC YC ZC (rotational loads: not used)
    type(source_t) :: src
  end type body_load_t

  !> *INITIAL_VELOCITY, _NODE, _GENERATION.
  type, public :: initial_velocity_t
    integer :: target_kind = ON_ALL_NODES
    integer :: target_id = 0, target = 0
    integer :: exempt_set_id = 0, exempt_set = 0
    real(wp) :: v(3) = 0.0_wp, omega_vector(3) = 0.0_wp
    real(wp) :: v_exempt(3) = 0.0_wp
    real(wp) :: omega = 0.0_wp               !< _GENERATION: angular velocity
    real(wp) :: center(3) = 0.0_wp, axis(3) = 0.0_wp
    logical :: generation = .false.          !< from _GENERATION: v + omega axis x (x - center)
    integer :: box_id = 0, box = 0           !< BOXID: only the nodes inside this box
    integer :: system_id = 0                 !< ICID: v, omega_vector, v_exempt and axis are
                                             !< given in this system (global after resolve)
    type(source_t) :: src
  end type initial_velocity_t

  !> *MAT_ADD_EROSION of a material (attached to it by resolve): its card values as read.
  type, public :: add_erosion_t
    integer :: material_id = 0              !< MID
    real(wp) :: limit(EROSION_CRITERIA) = 0.0_wp   !< the criteria's values (EROSION_*)
    real(wp) :: exclusion = 0.0_wp          !< EXCL: a value equal to it is not used
    integer :: conditions = 1               !< NCS
    type(source_t) :: src
  end type add_erosion_t

  !> *CONSTRAINED_GLOBAL: the nodes on a plane normal to a global axis are held (TC code).
  type, public :: global_constraint_t
    integer :: tc = 0                       !< translational constraint code (0-7)
    integer :: direction = 1                !< DIR: 1 x, 2 y, 3 z (the plane's normal)
    real(wp) :: point(3) = 0.0_wp           !< X Y Z: a point of the plane
    real(wp) :: tolerance = 0.0_wp          !< TOL (0: 1e-6 of the model's extent)
    type(source_t) :: src
  end type global_constraint_t

  !> *DEFINE_BOX: an axis-aligned box of the reference configuration.
  !> *DEFINE_COORDINATE_SYSTEM / _VECTOR / _NODES: a Cartesian system fixed in the reference
  !> configuration (_NODES with FLAG 1: moving with its nodes, for the SPCs in it).
  type, public :: coordinate_system_t
    integer :: id = 0
    integer :: kind = 0                      !< SYSTEM_BY_POINTS, _BY_VECTORS, _BY_NODES
    real(wp) :: points(3, 3) = 0.0_wp        !< by points: origin, on x, in x-y; by vectors:
                                             !< x axis, in x-y, (unused)
    integer :: node_ids(3) = 0               !< by nodes: origin, on x, in x-y (DIR: on the
                                             !< first axis, in its plane with the next)
    integer :: first_axis = 1                !< by nodes, DIR: 1 X, 2 Y, 3 Z, the axis of N1 N2
    logical :: moving = .false.              !< by nodes, FLAG 1: the system follows its nodes
                                             !< (the SPCs in it; explicit)
    integer :: nodes(3) = 0                  !< (resolve) by nodes: N1 N2 N3's mesh indices
    integer :: reference_id = 0              !< CIDL (by points): the system of the points
    real(wp) :: origin(3) = 0.0_wp           !< (resolve) global origin
    real(wp) :: axes(3, 3) = 0.0_wp          !< (resolve) global unit axes (columns x, y, z)
    logical :: resolved = .false.
    type(source_t) :: src
  end type coordinate_system_t
  integer, parameter, public :: SYSTEM_BY_POINTS = 1, SYSTEM_BY_VECTORS = 2, &
                                SYSTEM_BY_NODES = 3

  !> *DEFINE_VECTOR: from tail to head, in system CID (0: global).
  type, public :: vector_t
    integer :: id = 0
    real(wp) :: tail(3) = 0.0_wp, head(3) = 0.0_wp
    integer :: tail_node = 0, head_node = 0  !< *DEFINE_VECTOR_NODES: NODET, NODEH (ids)
    integer :: system_id = 0
    real(wp) :: direction(3) = 0.0_wp        !< (resolve) global unit vector
    type(source_t) :: src
  end type vector_t

  type, public :: box_t
    integer :: id = 0
    real(wp) :: low(3) = 0.0_wp, high(3) = 0.0_wp   !< XMN YMN ZMN, XMX YMX ZMX
    type(source_t) :: src
  end type box_t

  !> How a tie fails (contact_t%tiebreak): never (*CONTACT_TIED_), when
  !> (sigma_n/NFLS)^2 + (sigma_s/SFLS)^2 >= 1 with the tensile normal and the shear stress of
  !> the node's tie force over its area (TIEBREAK_STRESS), or when (f_n/NFLF)^NEN +
  !> (f_s/SFLF)^MES >= 1 with the forces themselves (TIEBREAK_FORCE).
  integer, parameter, public :: TIEBREAK_NONE = 0, TIEBREAK_STRESS = 1, TIEBREAK_FORCE = 2

  !> *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE(_MORTAR).
  type, public :: contact_t
    integer :: id = 0
    character(len=80) :: title = ''
    logical :: mortar = .false.
    logical :: eroding = .false.             !< *CONTACT_ERODING_... with EROSOP = 1: faces
                                             !< that erosion exposes join the surfaces
    logical :: single_surface = .false.      !< *CONTACT_AUTOMATIC_SINGLE_SURFACE: SURFA
                                             !< against itself (SURFB not used)
    logical :: tied = .false.                !< *CONTACT_TIED_...: SURFA's nodes tied to
                                             !< SURFB (model%ties, not model%contacts)
    logical :: offset = .false.              !< tied: the _OFFSET or _CONSTRAINED_OFFSET form
    character(len=64) :: keyword = ''        !< tied, transducer: the keyword as written
    integer :: surf_a_id = 0, surf_b_id = 0, surf_a_type = 0, surf_b_type = 0
    integer :: surf_a = 0, surf_b = 0        !< set/part indices (after resolve)
    real(wp) :: fs = 0.0_wp, fd = 0.0_wp, dc = 0.0_wp, vc = 0.0_wp, vdc = 0.0_wp
    real(wp) :: birth = 0.0_wp, death = 1.0e20_wp
    real(wp) :: sfsa = 1.0_wp, sfsb = 1.0_wp, sast = 0.0_wp, sbst = 0.0_wp
    real(wp) :: sfsat = 1.0_wp, sfsbt = 1.0_wp, fsf = 1.0_wp, vsf = 1.0_wp
    integer :: soft = 0, ignore = 0, igap = 1
    real(wp) :: sofscl = 0.1_wp, penmax = 0.0_wp
    ! tiebreak (*CONTACT_..._TIEBREAK_...): a tie (model%ties) that fails node by node, and
    ! its companion contact (model%contacts) that acts at the nodes once released
    integer :: tiebreak = TIEBREAK_NONE      !< a tie: how it fails (TIEBREAK_*)
    real(wp) :: fail_normal = 0.0_wp         !< NFLS (stress) or NFLF (force), tension
    real(wp) :: fail_shear = 0.0_wp          !< SFLS (stress) or SFLF (force)
    real(wp) :: fail_exponent_normal = 2.0_wp  !< NEN (forces; 2 for the stresses)
    real(wp) :: fail_exponent_shear = 2.0_wp   !< MES (forces; 2 for the stresses)
    integer :: companion = 0                 !< tie: its contact in model%contacts; contact:
                                             !< the tie in model%ties it takes over from
    type(source_t) :: src
  end type contact_t

  !> Contact surface kinds: the SURFATYP/SURFBTYP codes of LS-DYNA stored in contact_t (4 for
  !> the SURFA of nodes-to-surface contacts, 5 and 6 for single-surface contacts only).
  integer, parameter, public :: SURFACE_SEGMENT_SET = 0, SURFACE_PART_SET = 2, &
                                SURFACE_PART = 3, SURFACE_NODE_SET = 4, SURFACE_ALL_PARTS = 5, &
                                SURFACE_ALL_BUT_SET = 6

  !> Shapes of rigid walls: *RIGIDWALL_PLANAR and the infinite *RIGIDWALL_GEOMETRIC_FLAT are
  !> planes; the others are *RIGIDWALL_GEOMETRIC_FLAT with edges, _PRISM, _CYLINDER, _SPHERE.
  integer, parameter, public :: WALL_PLANE = 1, WALL_FLAT = 2, WALL_PRISM = 3, &
                                WALL_CYLINDER = 4, WALL_SPHERE = 5

  !> *RIGIDWALL_PLANAR and *RIGIDWALL_GEOMETRIC_... (a kinematic wall: nodes are kept out).
  type, public :: rigid_wall_t
    integer :: id = 0
    integer :: shape = WALL_PLANE
    integer :: node_set_id = 0, node_set = 0, exempt_set_id = 0, exempt_set = 0
    integer :: box_id = 0, box = 0           !< BOXID: only the nodes inside this box
    real(wp) :: offset = 0.0_wp, birth = 0.0_wp, death = 1.0e20_wp, stiffness_scale = 1.0_wp
    real(wp) :: tail(3) = 0.0_wp, head(3) = 0.0_wp
    real(wp) :: friction = 0.0_wp, weld_velocity = 0.0_wp
    real(wp) :: edge(3) = 0.0_wp             !< XHEV YHEV ZHEV: the direction of the l edge
    real(wp) :: length_l = 0.0_wp, length_m = 0.0_wp, length_p = 0.0_wp  !< LENL LENM LENP
    real(wp) :: radius = 0.0_wp              !< RADCYL, RADSPH
    real(wp) :: length = 0.0_wp              !< LENCYL (0: infinite)
    integer :: motion_curve_id = 0, motion_curve = 0  !< _MOTION: LCID, its index
    integer :: motion_option = 0             !< OPT: 0 the curve is the velocity, 1 the
                                             !< displacement
    real(wp) :: motion_direction(3) = 0.0_wp !< VX VY VZ (unit after reading)
    character(len=48) :: keyword = '*RIGIDWALL_PLANAR' !< as written (messages)
    type(source_t) :: src
  end type rigid_wall_t

  !> Analysis controls and output requests (LS-DYNA defaults).
  type, public :: controls_t
    ! *CONTROL_TERMINATION
    logical :: have_termination = .false.
    real(wp) :: end_time = 0.0_wp
    integer :: end_cycle = 0
    real(wp) :: dt_min_fraction = 0.0_wp, end_energy = 0.0_wp, end_mass = 1.0e8_wp
    ! *CONTROL_TIMESTEP
    real(wp) :: dt_init = 0.0_wp, tssfac = 0.9_wp, dt2ms = 0.0_wp, tslimt = 0.0_wp
    integer :: isdo = 0, lctm = 0, ms1st = 0
    integer :: lctm_curve = 0                 !< LCTM's curve index (0: none)
    type(source_t) :: lctm_src                !< where LCTM was given
    ! *CONTROL_IMPLICIT_GENERAL
    integer :: imflag = 0, imform = 2, nsbs = 1, igs = 2
    real(wp) :: dt0 = 0.0_wp
    ! *CONTROL_IMPLICIT_SOLUTION
    integer :: nsolvr = 12, ilimit = 11, maxref = 15
    real(wp) :: dctol = 0.001_wp, ectol = 0.01_wp, rctol = 1.0e10_wp, lstol = 0.9_wp
    real(wp) :: abstol = 1.0e-10_wp
    integer :: dnorm = 2, diverg = 1, istif = 1, nlprint = 0, nlnorm = 2
    ! *CONTROL_IMPLICIT_AUTO
    integer :: iauto = 0, iteopt = 11, itewin = 5, kfail = 0
    real(wp) :: auto_dtmin = 0.0_wp, auto_dtmax = 0.0_wp, dtexp = 0.0_wp
    ! *DATABASE_*
    real(wp) :: plot_interval = 0.0_wp        !< *DATABASE_BINARY_D3PLOT DT (0: none)
    integer :: plot_count = 0                 !< NPLTC
    integer :: d3dump_cycles = 0              !< *DATABASE_BINARY_D3DUMP CYCL (0: none)
    integer :: d3dump_count = 0               !< its NPLTC: restart files at ENDTIM / NPLTC
    integer :: runrsf_cycles = 0              !< *DATABASE_BINARY_RUNRSF CYCL (0: none)
    real(wp) :: glstat_interval = 0.0_wp, rcforc_interval = 0.0_wp, nodout_interval = 0.0_wp
    type(source_t) :: plot_src, glstat_src, rcforc_src, nodout_src   !< where each DT was given
    integer :: n_history_nodes = 0
    integer, allocatable :: history_node_ids(:), history_nodes(:)
    integer :: n_history_sets = 0
    integer, allocatable :: history_set_ids(:), history_sets(:)   !< node-set ids, indices
    type(source_t), allocatable :: history_node_src(:), history_set_src(:)  !< where given
    ! *CONTROL_HOURGLASS
    integer :: ihq = 0                        !< IHQ (0: the default, 1)
    real(wp) :: qh = 0.0_wp                   !< QH (0: the default, 0.1)
    type(source_t) :: hourglass_src           !< where *CONTROL_HOURGLASS was given
    ! *MEFEM_ENRICHMENT
    real(wp) :: support_radius = 1.5_wp       !< a/L of the GMF approximation
    integer :: gmf_basis = 1                  !< 1 atan, 2 exp
    real(wp) :: bubble_mass = 0.0_wp          !< explicit bubble inertia / (rho V); 0 default
    character(len=80) :: title = ''
  end type controls_t

  !> *CONSTRAINED_RIGID_BODIES (a part merged into a rigid body: lead = master PIDL, part =
  !> PIDC) or *CONSTRAINED_EXTRA_NODES_NODE/_SET (nodes added to the rigid body of part lead).
  type, public :: rigid_constraint_t
    integer :: kind = 0                     !< RIGID_MERGE, RIGID_EXTRA_NODES or RIGID_NODAL
    integer :: lead_id = 0, lead = 0        !< the body's (master) part: id, index; nodal
                                            !< bodies: lead_id the body's PID (output), 0
    integer :: target_kind = 0              !< merge: ON_PART; extra nodes: ON_NODE/ON_NODE_SET;
                                            !< nodal: ON_NODE_SET, or ON_NODE (spot weld)
    integer :: target_id = 0, target = 0    !< the merged part, node or node set: id, index
    integer :: second_id = 0, second = 0    !< spot weld: the second node
    type(source_t) :: src
  end type rigid_constraint_t
  !> Kinds of rigid_constraint_t: *CONSTRAINED_RIGID_BODIES, *CONSTRAINED_EXTRA_NODES,
  !> *CONSTRAINED_NODAL_RIGID_BODY and *CONSTRAINED_SPOTWELD (a body of its nodes).
  integer, parameter, public :: RIGID_MERGE = 1, RIGID_EXTRA_NODES = 2, RIGID_NODAL = 3

  !> *ELEMENT_MASS(_NODE_SET) and *ELEMENT_MASS_PART(_SET): mass added at nodes.
  type, public :: added_mass_t
    integer :: target_kind = ON_NODE        !< ON_NODE, ON_NODE_SET, ON_PART or ON_PART_SET
    integer :: target_id = 0, target = 0    !< node, node set, part or part set: id, index
    integer :: element_id = 0               !< EID (*ELEMENT_MASS)
    real(wp) :: mass = 0.0_wp               !< MASS (on a node, or shared equally by a set's
                                            !< nodes), ADDMASS (parts)
    real(wp) :: final_mass = 0.0_wp         !< FINMASS (parts; 0: ADDMASS is used)
    type(source_t) :: src
  end type added_mass_t

  !> The whole model.
  type, public :: model_t
    type(nodes_t) :: nodes
    type(elements_t) :: elements
    integer :: n_parts = 0, n_sections = 0, n_materials = 0, n_sets = 0, n_curves = 0
    type(part_t), allocatable :: parts(:)
    type(section_t), allocatable :: sections(:)
    type(material_t), allocatable :: materials(:)
    type(set_t), allocatable :: sets(:)
    type(curve_t), allocatable :: curves(:)
    integer :: n_hourglasses = 0
    type(hourglass_t), allocatable :: hourglasses(:)
    integer :: n_spcs = 0, n_motions = 0, n_nodal_loads = 0, n_pressure_loads = 0
    integer :: n_initial_velocities = 0, n_contacts = 0, n_rigid_walls = 0
    integer :: n_body_loads = 0
    type(body_load_t), allocatable :: body_loads(:)   !< at most one per direction
    integer :: body_part_set_id = 0          !< *LOAD_BODY_PARTS PSID (0: all parts)
    integer :: body_part_set = 0             !< its index in sets (after resolve)
    type(source_t) :: body_part_src          !< where PSID was given
    type(spc_t), allocatable :: spcs(:)
    type(prescribed_motion_t), allocatable :: motions(:)
    type(nodal_load_t), allocatable :: nodal_loads(:)
    type(pressure_load_t), allocatable :: pressure_loads(:)
    type(initial_velocity_t), allocatable :: initial_velocities(:)
    type(contact_t), allocatable :: contacts(:)
    integer :: n_ties = 0                    !< tied contacts (*CONTACT_TIED_...)
    type(contact_t), allocatable :: ties(:)
    integer :: n_transducers = 0             !< *CONTACT_FORCE_TRANSDUCER_PENALTY
    type(contact_t), allocatable :: transducers(:)
    type(rigid_wall_t), allocatable :: rigid_walls(:)
    integer :: n_rigid_constraints = 0
    type(rigid_constraint_t), allocatable :: rigid_constraints(:)
    integer :: n_added_masses = 0
    type(added_mass_t), allocatable :: added_masses(:)
    integer :: n_boxes = 0
    type(box_t), allocatable :: boxes(:)
    integer :: n_systems = 0, n_vectors = 0
    type(coordinate_system_t), allocatable :: systems(:)
    type(vector_t), allocatable :: vectors(:)
    integer :: n_add_erosions = 0
    type(add_erosion_t), allocatable :: add_erosions(:)
    integer :: n_global_constraints = 0
    type(global_constraint_t), allocatable :: global_constraints(:)
    type(controls_t) :: controls
    integer :: dimension = 3                  !< 2 for plane strain shells-only models
    !> Ids of materials and sections whose keyword was rejected (unsupported, or with errors):
    !> a part naming one is not reported again as naming an undefined one
    integer, allocatable :: rejected_material_ids(:), rejected_section_ids(:)
  end type model_t

contains

  !> The point x (reference configuration) lies in the box (its faces included).
  pure logical function box_holds(box, x)
    type(box_t), intent(in) :: box           !< the box
    real(wp), intent(in) :: x(3)             !< point
    box_holds = all(x >= box%low) .and. all(x <= box%high)
  end function box_holds

end module mefem_model
