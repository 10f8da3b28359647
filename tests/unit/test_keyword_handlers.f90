!> Keyword handlers: reads tests/decks/good/kw_all_fixed.k (fixed columns, blank fields for
!> defaults, a *PARAMETER reference in a material card, a *DEFINE_CURVE in long format) and
!> kw_all_comma.k (the same deck in comma format, materials by their numeric aliases),
!> checks every stored value of both, then resolves the references with resolve_conditions
!> and checks the indices. Decks written by the test (tests/out/kw_unit/) check the
!> ranges of a large *SET_NODE_LIST_GENERATE, a curve offset, and a comma card whose field
!> follows unread fields.
program test_keyword_handlers
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal, project_root
  use mefem_errors, only: reset_input_errors, input_error_count
  use mefem_file_system, only: make_directory
  use mefem_model, only: model_t, MAT_ELASTIC, MAT_PIECEWISE_LINEAR, MAT_POWER_LAW, &
                         MAT_RIGID, MAT_MOONEY_RIVLIN, SET_NODE, SET_PART, SET_SEGMENT, &
                         ON_NODE, ON_NODE_SET, ON_PART, ON_ALL_NODES
  use mefem_keyword_reader, only: read_deck
  use mefem_id_map, only: id_map_t, id_map_build, id_map_find
  use mefem_resolve_conditions, only: resolve_conditions
  implicit none

  character(len=:), allocatable :: root
  real(wp), parameter :: TIGHT = 1.0e-14_wp

  call test_start('keyword_handlers')
  root = project_root()
  call check_deck(root//'/tests/decks/good/kw_all_fixed.k', 'fixed')
  call check_deck(root//'/tests/decks/good/kw_all_comma.k', 'comma')
  call check_generated_deck(root//'/tests/out/kw_unit')
  call test_finish()

contains

  !> Read one of the two decks, check what was stored, resolve, check the indices.
  subroutine check_deck(path, label)
    character(len=*), intent(in) :: path    !< the deck
    character(len=*), intent(in) :: label   !< 'fixed' or 'comma', prefixes check names
    type(model_t) :: model
    type(id_map_t) :: node_map, part_map, material_map, curve_map
    integer :: n_errors, k
    integer, allocatable :: part_ids(:)
    call reset_input_errors()
    call read_deck(path, model, n_errors)
    call check_equal(n_errors, 0, label//': deck read without errors')
    if (n_errors /= 0) return
    call check_materials(model, label)
    call check_sets(model, label)
    call check_conditions(model, label)
    call check_contacts(model, label)
    call check_controls(model, label)
    ! resolve with maps built as model_resolve builds them
    call id_map_build(model%nodes%id, model%nodes%n, node_map)
    part_ids = [(model%parts(k)%id, k = 1, model%n_parts)]
    call id_map_build(part_ids, model%n_parts, part_map)
    call resolve_conditions(model, node_map, part_map, material_map, curve_map)
    call check_equal(input_error_count(), 0, label//': references resolve without errors')
    call check_resolved(model, material_map, curve_map, label)
  end subroutine check_deck

  !> The six materials.
  subroutine check_materials(model, label)
    type(model_t), intent(in) :: model      !< the model read
    character(len=*), intent(in) :: label   !< check-name prefix
    call check_equal(model%n_materials, 6, label//': six materials')
    if (model%n_materials /= 6) return
    associate (m => model%materials)
      call check(all(m(1:6)%id == [1, 2, 6, 3, 4, 5]), label//': material ids in deck order')
      call check(all(m(1:6)%kind == [MAT_ELASTIC, MAT_PIECEWISE_LINEAR, MAT_PIECEWISE_LINEAR, &
                                     MAT_POWER_LAW, MAT_MOONEY_RIVLIN, MAT_RIGID]), &
                 label//': material kinds (names and numeric aliases)')
      ! *MAT_ELASTIC_TITLE with E = &young
      call check(m(1)%title == 'steel', label//': MAT_ELASTIC title')
      call check_close(m(1)%young, 210000.0_wp, TIGHT, label//': MAT_ELASTIC E from &young')
      call check_close(m(1)%density, 7.8e-9_wp, TIGHT, label//': MAT_ELASTIC RO')
      call check_close(m(1)%poisson, 0.3_wp, TIGHT, label//': MAT_ELASTIC PR')
      ! *MAT_PIECEWISE_LINEAR_PLASTICITY: blank FAIL, LCSS, EPS/ES table
      call check_close([m(2)%young, m(2)%yield_stress, m(2)%tangent_modulus], &
                       [2.0e5_wp, 250.0_wp, 1000.0_wp], TIGHT, label//': MAT_024 E SIGY ETAN')
      call check_close(m(2)%failure_strain, 0.0_wp, TIGHT, label//': MAT_024 FAIL default '// &
                       '(0: no failure)')
      call check_equal(m(2)%lcss, 1, label//': MAT_024 LCSS')
      call check_equal(m(2)%n_points, 3, label//': MAT_024 EPS/ES points')
      call check_close(m(2)%eps(1:3), [0.0_wp, 0.1_wp, 0.2_wp], TIGHT, label//': MAT_024 EPS')
      call check_close(m(2)%es(1:3), [250.0_wp, 300.0_wp, 320.0_wp], TIGHT, &
                       label//': MAT_024 ES')
      ! *MAT_024_TITLE without EPS/ES cards
      call check(m(3)%title == 'alias without EPS/ES cards', label//': MAT_024 alias title')
      call check_close([m(3)%yield_stress, m(3)%failure_strain, m(3)%cowper_c, m(3)%cowper_p], &
                       [300.0_wp, 0.5_wp, 40.0_wp, 5.0_wp], TIGHT, &
                       label//': MAT_024 alias SIGY FAIL C P')
      call check_equal(m(3)%n_points, 0, label//': MAT_024 missing EPS/ES cards = no table')
      ! *MAT_POWER_LAW_PLASTICITY
      call check_close([m(4)%k_strength, m(4)%n_exponent, m(4)%cowper_c, m(4)%cowper_p, &
                        m(4)%yield_stress, m(4)%vp, m(4)%failure_strain], &
                       [500.0_wp, 0.2_wp, 40.0_wp, 5.0_wp, 100.0_wp, 1.0_wp, 0.8_wp], TIGHT, &
                       label//': MAT_018 K N SRC SRP SIGY VP EPSF')
      ! *MAT_MOONEY-RIVLIN_RUBBER: E = 4 (A + B) (1 + PR)
      call check_close([m(5)%density, m(5)%poisson, m(5)%mr_a, m(5)%mr_b], &
                       [1.1e-9_wp, 0.495_wp, 0.6_wp, 0.15_wp], TIGHT, &
                       label//': MAT_027 RO PR A B')
      call check_close(m(5)%young, 4.0_wp*0.75_wp*1.495_wp, 1.0e-13_wp, &
                       label//': MAT_027 equivalent E')
      ! *MAT_RIGID
      call check(m(6)%cmo == 1 .and. m(6)%con1 == 7 .and. m(6)%con2 == 7, &
                 label//': MAT_RIGID CMO CON1 CON2')
      call check_close(m(6)%young, 2.1e5_wp, TIGHT, label//': MAT_RIGID E')
    end associate
  end subroutine check_materials

  !> The seven sets.
  subroutine check_sets(model, label)
    type(model_t), intent(in) :: model      !< the model read
    character(len=*), intent(in) :: label   !< check-name prefix
    call check_equal(model%n_sets, 7, label//': seven sets')
    if (model%n_sets /= 7) return
    associate (s => model%sets)
      call check(all(s(1:7)%kind == [SET_NODE, SET_NODE, SET_NODE, SET_PART, SET_PART, &
                                     SET_SEGMENT, SET_SEGMENT]), label//': set kinds')
      call check(all(s(1:7)%id == [1, 2, 3, 1, 2, 1, 2]), label//': set ids')
      call check(s(1)%title == 'bottom' .and. s(7)%title == 'tool', label//': set titles')
      call check(same(s(1)%member_ids, [1, 2, 3]), label//': SET_NODE_LIST members, 0 ignored')
      call check(same(s(2)%member_ids, [1, 4, 6, 7]) .and. s(2)%generated, &
                 label//': SET_NODE_LIST_GENERATE ranges kept (resolved against the nodes)')
      call check(same(s(3)%member_ids, [4]), label//': SET_NODE alias, blank ignored')
      call check(same(s(4)%member_ids, [1]) .and. same(s(5)%member_ids, [2]), &
                 label//': SET_PART_LIST and SET_PART members')
      call check(same(s(6)%member_ids, [1, 3, 2, 2]), label//': SET_SEGMENT triangle N4 = N3')
      call check(same(s(7)%member_ids, [5, 6, 7, 8]), label//': SET_SEGMENT quadrilateral')
    end associate
  end subroutine check_sets

  !> Boundary conditions, curves, loads, initial velocities.
  subroutine check_conditions(model, label)
    type(model_t), intent(in) :: model      !< the model read
    character(len=*), intent(in) :: label   !< check-name prefix
    call check_equal(model%n_spcs, 2, label//': two SPCs')
    if (model%n_spcs == 2) then
      call check(model%spcs(1)%target_kind == ON_NODE_SET .and. model%spcs(1)%target_id == 1 &
                 .and. all(model%spcs(1)%dof .eqv. [.false., .false., .true., .false., &
                 .false., .false.]), label//': BOUNDARY_SPC_SET_ID NSID and DOF flags')
      call check(model%spcs(2)%target_kind == ON_NODE .and. all(model%spcs(2)%dof), &
                 label//': BOUNDARY_SPC_NODE all six flags')
    end if
    call check_equal(model%n_motions, 3, label//': three prescribed motions')
    if (model%n_motions == 3) then
      associate (p => model%motions)
        call check(p(1)%target_kind == ON_NODE_SET .and. p(1)%target_id == 3 .and. &
                   p(1)%dof == 3 .and. p(1)%vad == 2 .and. p(1)%curve_id == 1, &
                   label//': PRESCRIBED_MOTION_SET NSID DOF VAD LCID')
        call check_close([p(1)%scale, p(1)%death, p(1)%birth], [-0.5_wp, 1.0e28_wp, 0.0_wp], &
                         TIGHT, label//': PRESCRIBED_MOTION_SET SF and default DEATH BIRTH')
        call check(p(2)%target_kind == ON_PART .and. p(2)%target_id == 2 .and. &
                   p(2)%curve_id == 2 .and. p(2)%vad == 0, label//': PRESCRIBED_MOTION_RIGID_ID')
        call check_close([p(2)%scale, p(2)%death], [1.0_wp, 0.5_wp], TIGHT, &
                         label//': PRESCRIBED_MOTION_RIGID default SF, DEATH')
        call check(p(3)%target_kind == ON_NODE .and. p(3)%target_id == 2 .and. &
                   p(3)%dof == 1 .and. p(3)%vad == 1, label//': PRESCRIBED_MOTION_NODE')
      end associate
    end if
    call check_equal(model%n_curves, 2, label//': two curves')
    if (model%n_curves == 2) then
      associate (c => model%curves)
        call check(c(1)%id == 1 .and. c(1)%title == 'ramp' .and. c(1)%n == 2, &
                   label//': DEFINE_CURVE_TITLE id, title, points')
        call check_close(c(1)%t, [2.0_wp, 4.0_wp], TIGHT, label//': curve t = SFA (A + OFFA)')
        call check_close(c(1)%f, [1.5_wp, 4.5_wp], TIGHT, label//': curve f = SFO (O + OFFO)')
        call check(c(2)%id == 2 .and. c(2)%n == 3, label//': long-format DEFINE_CURVE')
        call check_close(c(2)%t, [0.0_wp, 0.5_wp, 1.0_wp], TIGHT, label//': long curve t')
        call check_close(c(2)%f, [0.0_wp, 10.0_wp, 10.0_wp], TIGHT, label//': long curve f')
      end associate
    end if
    call check_equal(model%n_nodal_loads, 2, label//': two nodal loads')
    if (model%n_nodal_loads == 2) then
      associate (l => model%nodal_loads)
        call check(l(1)%target_kind == ON_NODE .and. l(1)%target_id == 4 .and. &
                   l(1)%dof == 3 .and. l(1)%curve_id == 1 .and. l(1)%scale == 2.5_wp, &
                   label//': LOAD_NODE_POINT')
        call check(l(2)%target_kind == ON_NODE_SET .and. l(2)%target_id == 1 .and. &
                   l(2)%dof == 1 .and. l(2)%curve_id == 2 .and. l(2)%scale == 1.0_wp, &
                   label//': LOAD_NODE_SET with default SF')
      end associate
    end if
    call check_equal(model%n_pressure_loads, 2, label//': two pressure loads')
    if (model%n_pressure_loads == 2) then
      associate (l => model%pressure_loads)
        call check(l(1)%curve_id == 1 .and. l(1)%scale == 1.0_wp .and. &
                   l(1)%arrival == 0.1_wp .and. all(l(1)%node_ids == [1, 2, 4, 4]) .and. &
                   l(1)%set_id == 0, label//': LOAD_SEGMENT (triangle, default SF)')
        call check(l(2)%set_id == 1 .and. l(2)%curve_id == 2 .and. l(2)%scale == 4.0_wp, &
                   label//': LOAD_SEGMENT_SET_ID')
      end associate
    end if
    call check_equal(model%n_body_loads, 2, label//': two body loads')
    if (model%n_body_loads == 2) then
      associate (b => model%body_loads)
        call check(b(1)%direction == 3 .and. b(1)%curve_id == 2 .and. b(1)%scale == 9810.0_wp &
                   .and. b(1)%dr_curve_id == 0, label//': LOAD_BODY_Z LCID SF')
        call check(b(2)%direction == 1 .and. b(2)%curve_id == 1 .and. b(2)%scale == 1.0_wp &
                   .and. all(b(2)%centre == [1.0_wp, 0.0_wp, 0.0_wp]), &
                   label//': LOAD_BODY_X default SF, XC')
      end associate
    end if
    call check_equal(model%body_part_set_id, 1, label//': LOAD_BODY_PARTS PSID')
    call check_equal(model%n_initial_velocities, 4, label//': four initial velocities')
    if (model%n_initial_velocities == 4) then
      associate (v => model%initial_velocities)
        call check(v(1)%target_kind == ON_ALL_NODES .and. all(v(1)%v == [1.0_wp, 2.0_wp, &
                   3.0_wp]), label//': INITIAL_VELOCITY on all nodes')
        call check(v(2)%target_kind == ON_NODE_SET .and. v(2)%target_id == 2 .and. &
                   v(2)%exempt_set_id == 3 .and. all(v(2)%v == [5.0_wp, 0.0_wp, 0.0_wp]) &
                   .and. all(v(2)%v_exempt == [7.0_wp, 8.0_wp, 9.0_wp]), &
                   label//': INITIAL_VELOCITY with exempted nodes')
        call check(v(3)%target_kind == ON_NODE .and. v(3)%target_id == 4 .and. &
                   all(v(3)%v == [-1.0_wp, 0.0_wp, 0.0_wp]), label//': INITIAL_VELOCITY_NODE')
        call check(v(4)%generation .and. v(4)%target_kind == ON_PART .and. &
                   v(4)%target_id == 1 .and. v(4)%omega == 10.0_wp .and. &
                   all(v(4)%axis == [0.0_wp, 0.0_wp, 1.0_wp]) .and. &
                   all(v(4)%v == [0.0_wp, 0.0_wp, 1.0_wp]), &
                   label//': INITIAL_VELOCITY_GENERATION (axis normalised)')
      end associate
    end if
  end subroutine check_conditions

  !> Contacts and the rigid wall.
  subroutine check_contacts(model, label)
    type(model_t), intent(in) :: model      !< the model read
    character(len=*), intent(in) :: label   !< check-name prefix
    call check_equal(model%n_contacts, 2, label//': two contacts')
    if (model%n_contacts == 2) then
      associate (c => model%contacts)
        call check(c(1)%id == 5 .and. c(1)%title == 'die contact' .and. c(1)%mortar, &
                   label//': CONTACT _MORTAR_ID id, heading, mortar')
        call check(c(1)%surf_a_id == 1 .and. c(1)%surf_b_id == 2 .and. &
                   c(1)%surf_a_type == 3 .and. c(1)%surf_b_type == 3, &
                   label//': CONTACT card 1')
        call check_close([c(1)%fs, c(1)%fd, c(1)%sfsa, c(1)%sfsb, c(1)%death], &
                         [0.2_wp, 0.1_wp, 1.0_wp, 1.0_wp, 1.0e20_wp], TIGHT, &
                         label//': CONTACT FS FD, blank card 3 defaults, DT default')
        call check(c(1)%soft == 2 .and. c(1)%igap == 2 .and. c(1)%ignore == 1, &
                   label//': CONTACT optional cards A and C')
        call check_close([c(1)%sofscl, c(1)%penmax], [0.1_wp, 0.05_wp], TIGHT, &
                         label//': CONTACT SOFSCL default, PENMAX (card B)')
        call check(.not. c(2)%mortar .and. c(2)%id == 0 .and. c(2)%surf_a_type == 0 .and. &
                   c(2)%surf_b_type == 2 .and. c(2)%igap == 1 .and. c(2)%soft == 0, &
                   label//': CONTACT without options, defaults of absent optional cards')
        call check_close([c(2)%fs, c(2)%sfsa, c(2)%sfsb], [0.0_wp, 1.5_wp, 2.0_wp], TIGHT, &
                         label//': CONTACT blank card 2, card 3 SFSA SFSB')
      end associate
    end if
    call check_equal(model%n_rigid_walls, 1, label//': one rigid wall')
    if (model%n_rigid_walls == 1) then
      associate (w => model%rigid_walls(1))
        call check(w%id == 4 .and. w%node_set_id == 2 .and. w%exempt_set_id == 0, &
                   label//': RIGIDWALL_PLANAR_ID id and NSID')
        call check_close([w%offset, w%death, w%stiffness_scale, w%friction], &
                         [0.01_wp, 1.0e20_wp, 1.0_wp, 0.3_wp], TIGHT, &
                         label//': RIGIDWALL_PLANAR OFFSET, defaults, FRIC')
        call check_close([w%tail, w%head], [0.0_wp, 0.0_wp, -1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                         TIGHT, label//': RIGIDWALL_PLANAR tail and head')
      end associate
    end if
  end subroutine check_contacts

  !> Controls and output requests.
  subroutine check_controls(model, label)
    type(model_t), intent(in) :: model      !< the model read
    character(len=*), intent(in) :: label   !< check-name prefix
    associate (c => model%controls)
      call check(c%title == 'keyword handlers', label//': title')
      call check_close([c%end_time, c%dt_init, c%tssfac, c%dt2ms], &
                       [1.0_wp, 0.0_wp, 0.8_wp, -1.0e-6_wp], TIGHT, &
                       label//': CONTROL_TIMESTEP DTINIT TSSFAC DT2MS')
      call check_equal(c%lctm, 2, label//': CONTROL_TIMESTEP LCTM')
      call check(c%imflag == 1 .and. c%dt0 == 0.01_wp .and. c%imform == 2 .and. &
                 c%nsbs == 1 .and. c%igs == 2, label//': CONTROL_IMPLICIT_GENERAL')
      call check(c%nsolvr == 12 .and. c%ilimit == 20 .and. c%maxref == 15 .and. &
                 c%dnorm == 1 .and. c%diverg == 2 .and. c%istif == 1, &
                 label//': CONTROL_IMPLICIT_SOLUTION integers and defaults')
      call check_close([c%dctol, c%ectol, c%rctol, c%lstol, c%abstol], &
                       [1.0e-4_wp, 0.01_wp, 1.0e10_wp, 0.9_wp, 1.0e-10_wp], TIGHT, &
                       label//': CONTROL_IMPLICIT_SOLUTION tolerances and defaults')
      call check(c%iauto == 1 .and. c%iteopt == 11 .and. c%itewin == 8, &
                 label//': CONTROL_IMPLICIT_AUTO IAUTO, ITEOPT default, ITEWIN')
      call check_close([c%auto_dtmin, c%auto_dtmax], [1.0e-5_wp, 0.05_wp], TIGHT, &
                       label//': CONTROL_IMPLICIT_AUTO DTMIN DTMAX')
      call check_close([c%plot_interval, c%glstat_interval, c%rcforc_interval, &
                        c%nodout_interval], [0.1_wp, 0.01_wp, 0.02_wp, 0.03_wp], TIGHT, &
                       label//': DATABASE intervals')
      call check(c%n_history_nodes == 3 .and. c%n_history_sets == 2, &
                 label//': DATABASE_HISTORY_NODE(_SET) counts')
      if (c%n_history_nodes == 3 .and. c%n_history_sets == 2) &
        call check(all(c%history_node_ids(1:3) == [1, 4, 2]) .and. &
                   all(c%history_set_ids(1:2) == [1, 2]), label//': history ids')
      call check(c%support_radius == 2.0_wp .and. c%gmf_basis == 2, &
                 label//': MEFEM_ENRICHMENT SUPPORT BASIS')
    end associate
  end subroutine check_controls

  !> Indices after resolve_conditions (node and part indices equal their ids here).
  subroutine check_resolved(model, material_map, curve_map, label)
    type(model_t), intent(in) :: model                      !< the resolved model
    type(id_map_t), intent(in) :: material_map, curve_map   !< maps returned
    character(len=*), intent(in) :: label                   !< check-name prefix
    call check(id_map_find(material_map, 6) == 3 .and. id_map_find(material_map, 5) == 6 &
               .and. id_map_find(material_map, 9) == 0, label//': material map')
    call check(id_map_find(curve_map, 2) == 2 .and. id_map_find(curve_map, 3) == 0, &
               label//': curve map')
    if (model%n_sets /= 7 .or. model%n_materials /= 6 .or. model%n_contacts /= 2) return
    call check_equal(model%materials(2)%lcss_curve, 1, label//': LCSS resolved')
    call check(same(model%sets(2)%members, [1, 2, 3, 4, 6, 7]) .and. &
               same(model%sets(5)%members, [2]) .and. &
               same(model%sets(6)%members, [1, 3, 2, 2]), label//': set members resolved')
    call check(model%spcs(1)%target == 1 .and. model%spcs(2)%target == 1, &
               label//': SPC targets')
    call check(model%motions(1)%target == 3 .and. model%motions(2)%target == 2 .and. &
               model%motions(1)%curve == 1 .and. model%motions(2)%curve == 2, &
               label//': prescribed motion targets and curves')
    call check(model%nodal_loads(2)%target == 1 .and. model%nodal_loads(2)%curve == 2, &
               label//': nodal load set and curve')
    call check(all(model%pressure_loads(1)%nodes == [1, 2, 4, 4]) .and. &
               model%pressure_loads(2)%set == 6, label//': pressure segment and set')
    call check(model%initial_velocities(2)%target == 2 .and. &
               model%initial_velocities(2)%exempt_set == 3 .and. &
               model%initial_velocities(4)%target == 1, label//': initial velocity targets')
    call check(model%contacts(1)%surf_a == 1 .and. model%contacts(1)%surf_b == 2 .and. &
               model%contacts(2)%surf_a == 6 .and. model%contacts(2)%surf_b == 5, &
               label//': contact surfaces by type (part, segment set, part set)')
    call check(model%rigid_walls(1)%node_set == 2, label//': rigid wall node set')
    if (model%n_body_loads == 2) call check(model%body_loads(1)%curve == 2 .and. &
        model%body_loads(2)%curve == 1 .and. model%body_part_set == 4, &
        label//': body load curves and part set')
    call check(same(model%controls%history_nodes, [1, 4, 2]) .and. &
               same(model%controls%history_sets, [1, 2]), label//': history nodes and sets')
  end subroutine check_resolved

  !> A deck written here: a GENERATE range of 100000 ids plus a one-id range, and a curve
  !> with an ordinate offset (comma format with blank fields).
  subroutine check_generated_deck(dir)
    character(len=*), intent(in) :: dir   !< output directory
    type(model_t) :: model
    integer :: unit, n_errors
    logical :: ok
    call make_directory(dir, ok)
    call check(ok, 'generated: output directory')
    if (.not. ok) return
    open(newunit=unit, file=dir//'/generate.k', status='replace', action='write')
    write(unit, '(a)') '*KEYWORD', '*SET_NODE_LIST_GENERATE', '7,', '1,100000,200001,200001', &
        '*DEFINE_CURVE', '9,,,,,-1.0', '0.0,1.0', '2.0,1.0', '*END'
    close(unit)
    call reset_input_errors()
    call read_deck(dir//'/generate.k', model, n_errors)
    call check_equal(n_errors, 0, 'generated: deck read without errors')
    if (n_errors /= 0 .or. model%n_sets /= 1 .or. model%n_curves /= 1) return
    ! the ranges as given, not their 100001 ids: memory follows the nodes that exist
    ! (resolve_sets), not the width of the ranges
    call check_equal(model%sets(1)%n, 2, 'generated: GENERATE ranges kept')
    call check(same(model%sets(1)%member_ids, [1, 100000, 200001, 200001]), &
               'generated: GENERATE ranges B E')
    call check_close(model%curves(1)%f, [0.0_wp, 0.0_wp], TIGHT, 'generated: curve OFFO -1')
    ! a field after unread columns (LCID after SGL SW ST): in comma format the 4th entry
    open(newunit=unit, file=dir//'/gap.k', status='replace', action='write')
    write(unit, '(a)') '*KEYWORD', '*MAT_MOONEY-RIVLIN_RUBBER', '1,1.0e-9,0.49,0.5,0.1', &
        ',,,5', '*END'
    close(unit)
    call reset_input_errors()
    call read_deck(dir//'/gap.k', model, n_errors)
    call check_equal(n_errors, 1, 'generated: comma card, LCID after 3 unread fields read')
  end subroutine check_generated_deck

  !> True when an allocated list equals the expected ids.
  logical function same(list, expected)
    integer, allocatable, intent(in) :: list(:)   !< the list
    integer, intent(in) :: expected(:)            !< expected entries
    same = .false.
    if (.not. allocated(list)) return
    if (size(list) /= size(expected)) return
    same = all(list == expected)
  end function same

end program test_keyword_handlers
