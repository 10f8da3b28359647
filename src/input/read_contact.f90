!> Keyword handlers for contact and rigid walls: *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE and
!> *CONTACT_AUTOMATIC_SINGLE_SURFACE (options MORTAR, ID, TITLE, MPP; the same cards, SURFB
!> and SURFBTYP not used by the single surface), the tied contacts *CONTACT_TIED_SURFACE_TO_
!> SURFACE and _NODES_TO_SURFACE (options OFFSET, CONSTRAINED_OFFSET; the same cards, into
!> model%ties), *CONTACT_FORCE_TRANSDUCER_PENALTY (SURFA only, into model%transducers), the
!> eroding contacts *CONTACT_ERODING_... (the same cards and card 4, ISYM EROSOP IADJ) and
!> *RIGIDWALL_PLANAR (option ID).
!>
!> Contact card order (LS-DYNA manual): [_ID/_TITLE: CID HEADING] [_MPP: IGNORE BCKT LCBCKT
!> NS2TRK INITITR PARMAX - CPARM8, and an optional second card starting with '&'] / card 1
!> SURFA SURFB SURFATYP SURFBTYP SABOXID SBBOXID SAPR SBPR / card 2 FS FD DC VC VDC PENCHK BT
!> DT / card 3 SFSA SFSB SAST SBST SFSAT SFSBT FSF VSF / optional cards A-F, of which SOFT and
!> SOFSCL (A), PENMAX (B) and IGAP and IGNORE (C) are used.
module mefem_read_contact
  use mefem_kinds, only: wp
  use mefem_strings, only: itoa, rtoa, to_upper
  use mefem_cards, only: reader_t, card_t, next_card, split_card, get_int, get_real, &
                         card_error, card_warning, keyword_error
  use mefem_card_layouts, only: read_layout_card, real_field, int_field, card_fields_t
  use mefem_card_helpers, only: has_option, read_id_card, quoted_real, reject_extra_cards, &
                                skip_extra_cards, read_id_option
  use mefem_deck_source, only: deck_push_back
  use mefem_model, only: model_t, contact_t, rigid_wall_t, source_t, FS_FROM_PARTS, &
                         TIEBREAK_STRESS, TIEBREAK_FORCE, WALL_PLANE, WALL_FLAT, WALL_PRISM, WALL_CYLINDER, WALL_SPHERE
  implicit none
  private

  public :: read_contact_surface_to_surface, read_rigidwall_planar, read_rigidwall_geometric

  !> Forms of the contact keywords read by read_contact_surface_to_surface.
  integer, parameter, public :: FORM_SURFACE_TO_SURFACE = 1, FORM_SINGLE_SURFACE = 2, &
                                FORM_NODES_TO_SURFACE = 3, FORM_TIED = 4, FORM_TIED_NODES = 5, &
                                FORM_TRANSDUCER = 6, FORM_TIEBREAK = 7, &
                                FORM_TIEBREAK_NODES = 8, FORM_TIEBREAK_AUTOMATIC = 9

  integer, parameter :: W_10(8) = 10          !< standard 8 x 10 card
  integer, parameter :: N_OPTIONAL = 6        !< optional cards A to F
  !> The contacts' cards in mefem_card_layouts (optional card A is card CARD_A there, B and C
  !> follow)
  character(len=*), parameter :: LAYOUT = 'CONTACT_AUTOMATIC_SURFACE_TO_SURFACE'
  integer, parameter :: CARD_A = 101

contains

  !> One interface of the contact keywords that share LS-DYNA's cards 1-3 and A-F, by form:
  !> FORM_SURFACE_TO_SURFACE *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE(_MORTAR)(_ID|_TITLE)(_MPP)
  !> (and the forming contacts), FORM_SINGLE_SURFACE *CONTACT_AUTOMATIC_SINGLE_SURFACE(...),
  !> FORM_NODES_TO_SURFACE the nodes-to-surface contacts (SURFA may be a node set), FORM_TIED
  !> and FORM_TIED_NODES the tied contacts (into model%ties), FORM_TRANSDUCER
  !> *CONTACT_FORCE_TRANSDUCER_PENALTY (into model%transducers), FORM_TIEBREAK,
  !> FORM_TIEBREAK_NODES and FORM_TIEBREAK_AUTOMATIC the tiebreak contacts (card 4 after card
  !> 3: a tie into model%ties that fails, and its companion contact into model%contacts).
  subroutine read_contact_surface_to_surface(rd, options, model, form)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    integer, intent(in) :: form                  !< FORM_* of the keyword
    type(contact_t) :: contact
    type(card_t) :: card, card1, card2, card3, mpp
    type(card_fields_t) :: f
    logical :: single_surface, tied, transducer, nodes_a, eroding, tiebreak
    logical :: got, ok, bad
    integer :: k, saboxid, sbboxid, mpp_ignore
    character(len=:), allocatable :: who
    contact%mortar = has_option(options, 'MORTAR')
    single_surface = form == FORM_SINGLE_SURFACE
    tiebreak = any(form == [FORM_TIEBREAK, FORM_TIEBREAK_NODES, FORM_TIEBREAK_AUTOMATIC])
    tied = form == FORM_TIED .or. form == FORM_TIED_NODES .or. tiebreak
    transducer = form == FORM_TRANSDUCER
    nodes_a = any(form == [FORM_NODES_TO_SURFACE, FORM_TIED_NODES, FORM_TIEBREAK_NODES])
    contact%single_surface = single_surface
    eroding = index(rd%keyword, '*CONTACT_ERODING_') == 1
    contact%tied = tied
    contact%offset = tied .and. has_option(options, 'OFFSET')
    if (tied .or. transducer) contact%keyword = trim(rd%keyword)
    if (has_option(options, 'ID') .or. has_option(options, 'TITLE')) then
      call read_id_card(rd, contact%id, contact%title, ok)
      if (.not. ok) then
        call skip_extra_cards(rd)
        return
      end if
    end if
    mpp_ignore = 0
    if (has_option(options, 'MPP')) then
      call next_card(rd, mpp, got, keep_blank=.true.)
      if (got) then
        ! IGNORE of the MPP card (as card C's IGNORE, which wins when both are given)
        call split_card(rd, mpp, W_10)
        call get_int(mpp, 1, 'IGNORE', mpp_ignore)
        if (mpp%bad) mpp_ignore = 0
        ! the optional second MPP card starts with '&'
        call next_card(rd, mpp, got, keep_blank=.true.)
        if (got) then
          if (mpp%length == 0 .or. mpp%text(1:1) /= '&') call push_back_card(rd)
        end if
      end if
    end if
    bad = .false.
    ! card 1
    call next_card(rd, card1, got)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (SURFA SURFB SURFATYP SURFBTYP ...)')
      return
    end if
    if (single_surface) then                   ! (SURFA may be blank: SURFATYP 5, all parts)
      call read_layout_card(rd, card1, LAYOUT, 1, f, [character(len=8) :: 'SURFA', 'SURFB'])
    else if (transducer) then
      call read_layout_card(rd, card1, LAYOUT, 1, f, [character(len=8) :: 'SURFB'])
    else
      call read_layout_card(rd, card1, LAYOUT, 1, f)
    end if
    contact%surf_a_id = int_field(f, 'SURFA')
    contact%surf_b_id = int_field(f, 'SURFB')
    contact%surf_a_type = int_field(f, 'SURFATYP')
    contact%surf_b_type = int_field(f, 'SURFBTYP')
    saboxid = int_field(f, 'SABOXID')
    sbboxid = int_field(f, 'SBBOXID')
    contact%src = source_t(card1%file, card1%line)
    bad = card1%bad
    who = 'contact'
    if (contact%id /= 0) who = 'contact '//itoa(contact%id)
    ! card 2
    call next_card(rd, card2, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card1, who//': missing card 2 (FS FD DC VC VDC PENCHK BT DT)')
      return
    end if
    call read_layout_card(rd, card2, LAYOUT, 2, f)
    contact%fs = real_field(f, 'FS')
    contact%fd = real_field(f, 'FD')
    contact%dc = real_field(f, 'DC')
    contact%vc = real_field(f, 'VC')
    contact%vdc = real_field(f, 'VDC')
    contact%birth = real_field(f, 'BT')
    contact%death = real_field(f, 'DT')
    bad = bad .or. card2%bad
    ! card 3 (required, may be blank)
    call next_card(rd, card3, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card2, who//': missing card 3 (SFSA SFSB SAST SBST SFSAT SFSBT FSF '// &
          'VSF; a blank line gives the defaults)')
      return
    end if
    call read_layout_card(rd, card3, LAYOUT, 3, f)
    contact%sfsa = real_field(f, 'SFSA')
    contact%sfsb = real_field(f, 'SFSB')
    contact%sast = real_field(f, 'SAST')
    contact%sbst = real_field(f, 'SBST')
    contact%sfsat = real_field(f, 'SFSAT')
    contact%sfsbt = real_field(f, 'SFSBT')
    contact%fsf = real_field(f, 'FSF')
    contact%vsf = real_field(f, 'VSF')
    bad = bad .or. card3%bad
    if (eroding) then
      call read_eroding_card(rd, card3, who, contact, bad)
      if (bad) then
        call skip_extra_cards(rd)
        return
      end if
    end if
    if (tiebreak) then
      call read_tiebreak_card(rd, card3, who, form, contact, bad)
      if (bad) then
        call skip_extra_cards(rd)
        return
      end if
    end if
    ! optional cards A, B, C (D, E, F accepted and not used)
    do k = 1, N_OPTIONAL
      call next_card(rd, card, got, keep_blank=.true.)
      if (.not. got) exit
      select case (k)
      case (1)
        call read_layout_card(rd, card, LAYOUT, CARD_A, f)
        contact%soft = int_field(f, 'SOFT')
        contact%sofscl = real_field(f, 'SOFSCL')
      case (2)
        call read_layout_card(rd, card, LAYOUT, CARD_A + 1, f)
        contact%penmax = real_field(f, 'PENMAX')
      case (3)
        call read_layout_card(rd, card, LAYOUT, CARD_A + 2, f)
        contact%igap = int_field(f, 'IGAP')
        contact%ignore = int_field(f, 'IGNORE')
      end select
      bad = bad .or. card%bad
      if (k <= 3 .and. .not. card%bad) call check_optional(card, k, contact, who, bad)
    end do
    call reject_extra_cards(rd, who)
    if (bad) return
    if (contact%ignore == 0 .and. mpp_ignore /= 0) contact%ignore = mpp_ignore
    ! read, not used: say so where LS-DYNA would compute something else
    if (contact%vc /= 0.0_wp .or. contact%vdc /= 0.0_wp) call card_warning(card2, who// &
        ': VC and VDC ignored (no friction limit from VC, no viscous contact damping)')
    if (tied) then
      if (contact%sast > 0.0_wp .or. contact%sbst /= 0.0_wp) call card_warning(card3, who// &
          ': SAST > 0 and SBST ignored: a negative SAST sets the tie''s tolerance, and the '// &
          'gap between the surfaces is kept as it is (doc/keywords.md 3.10)')
    else if (contact%sast /= 0.0_wp .or. contact%sbst /= 0.0_wp) then
      call card_warning(card3, who//': SAST and SBST ignored: contact surfaces lie on the '// &
          'elements'' faces and on the mid-surfaces of shells, with no thickness offset '// &
          '(doc/keywords.md 3.10)')
    end if
    call check_contact(card1, card2, card3, contact, nodes_a, transducer, who, saboxid, &
                       sbboxid, bad)
    if (((tied .and. .not. tiebreak) .or. transducer) .and. contact%fs /= 0.0_wp) &
      call card_warning(card2, who//': FS, FD and DC are not used by a '// &
                        trim(merge('tied contact    ', 'force transducer', tied)))
    if (.not. bad) then
      if (tiebreak) then
        ! the tie, and the contact that takes over at each node the tie releases
        contact%companion = model%n_contacts + 1
        call add_tie(model, contact)
        contact%tied = .false.
        contact%tiebreak = 0
        contact%companion = model%n_ties
        call add_contact(model, contact)
      else if (tied) then
        call add_tie(model, contact)
      else if (transducer) then
        call add_transducer(model, contact)
      else
        call add_contact(model, contact)
      end if
    end if
  end subroutine read_contact_surface_to_surface

  !> The card that follows card 3 in the *CONTACT_ERODING_... keywords, ISYM EROSOP IADJ
  !> (required; a blank line gives 0 0 0). EROSOP = 1: the faces that erosion exposes join the
  !> surfaces (contact%eroding); 0: only the faces of the first boundary, as LS-DYNA keeps
  !> (warned). IADJ: mefem's surfaces are always the boundaries of the parts named, faces
  !> next to other parts included (IADJ = 1); IADJ = 0 is warned. ISYM /= 0 is warned (no
  !> symmetry-plane faces are left out).
  subroutine read_eroding_card(rd, previous, who, contact, bad)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(card_t), intent(in) :: previous         !< card 3 (for a missing card's message)
    character(len=*), intent(in) :: who         !< 'contact N'
    type(contact_t), intent(inout) :: contact   !< eroding set
    logical, intent(inout) :: bad                !< a card was wrong
    type(card_t) :: card
    type(card_fields_t) :: f
    logical :: got
    integer :: isym, erosop, iadj
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(previous, who//': missing card 4 of the eroding contact (ISYM EROSOP '// &
          'IADJ; a blank line gives 0 0 0)')
      bad = .true.
      return
    end if
    call read_layout_card(rd, card, LAYOUT, 4, f)
    isym = int_field(f, 'ISYM')
    erosop = int_field(f, 'EROSOP')
    iadj = int_field(f, 'IADJ')
    if (card%bad) then
      bad = .true.
      return
    end if
    if (erosop /= 0 .and. erosop /= 1) then
      call card_error(card, who//': field EROSOP must be 0 or 1')
      bad = .true.
    end if
    if (iadj /= 0 .and. iadj /= 1) then
      call card_error(card, who//': field IADJ must be 0 or 1')
      bad = .true.
    end if
    if (bad) return
    contact%eroding = erosop == 1
    if (erosop == 0) call card_warning(card, who//': EROSOP = 0: the faces that erosion '// &
        'exposes do not join the contact (only the first boundary; EROSOP = 1 adds them)')
    if (iadj == 0) call card_warning(card, who//': IADJ = 0 read as 1: the surfaces are '// &
        'the boundaries of the parts named, faces next to other parts included')
    if (isym /= 0) call card_warning(card, who//': ISYM ignored: faces on symmetry planes '// &
        'are not left out of the surfaces')
  end subroutine read_eroding_card

  !> Card 4 of the tiebreak contacts (required), by form: *CONTACT_TIEBREAK_SURFACE_TO_SURFACE
  !> NFLS SFLS TBLCID THKOFF (failure stresses); *CONTACT_TIEBREAK_NODES_TO_SURFACE NFLF SFLF
  !> NEN MES (failure forces and exponents); *CONTACT_AUTOMATIC_(ONE_WAY_)SURFACE_TO_SURFACE_
  !> TIEBREAK OPTION NFLS SFLS PARAM ERATEN ERATES CT2CN CN, of which OPTION 2 (the nodes in
  !> contact at the start tied until the stress criterion fails them) runs; the other
  !> responses (permanent sticking of nodes that come into contact later, frictional sliding
  !> while tied, damage models) are errors naming the option.
  subroutine read_tiebreak_card(rd, previous, who, form, contact, bad)
    type(reader_t), intent(inout) :: rd          !< reading state
    type(card_t), intent(in) :: previous         !< card 3 (for a missing card's message)
    character(len=*), intent(in) :: who          !< 'contact N'
    integer, intent(in) :: form                  !< FORM_TIEBREAK*
    type(contact_t), intent(inout) :: contact    !< failure data set
    logical, intent(inout) :: bad                !< a card was wrong
    type(card_t) :: card
    type(card_fields_t) :: f
    character(len=:), allocatable :: normal, shear
    logical :: got
    integer :: option
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      select case (form)
      case (FORM_TIEBREAK_NODES)
        call card_error(previous, who//': missing card 4 of the tiebreak (NFLF SFLF NEN MES)')
      case (FORM_TIEBREAK)
        call card_error(previous, who//': missing card 4 of the tiebreak (NFLS SFLS TBLCID '// &
            'THKOFF)')
      case default
        call card_error(previous, who//': missing card 4 of the tiebreak (OPTION NFLS SFLS '// &
            'PARAM ERATEN ERATES CT2CN CN)')
      end select
      bad = .true.
      return
    end if
    select case (form)
    case (FORM_TIEBREAK_NODES)
      call read_layout_card(rd, card, 'CONTACT_TIEBREAK_NODES_TO_SURFACE', 4, f)
      contact%tiebreak = TIEBREAK_FORCE
      normal = 'NFLF'
      shear = 'SFLF'
      contact%fail_exponent_normal = real_field(f, 'NEN')
      contact%fail_exponent_shear = real_field(f, 'MES')
    case (FORM_TIEBREAK)
      call read_layout_card(rd, card, 'CONTACT_TIEBREAK_SURFACE_TO_SURFACE', 4, f)
      contact%tiebreak = TIEBREAK_STRESS
      normal = 'NFLS'
      shear = 'SFLS'
      if (.not. card%bad .and. int_field(f, 'TBLCID') /= 0) call fail(who//': TBLCID = '// &
          itoa(int_field(f, 'TBLCID'))//' (a post-failure stress curve) is not supported: '// &
          'give 0 (after failure the surfaces are in plain contact)')
    case default
      call read_layout_card(rd, card, 'CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', 4, f)
      contact%tiebreak = TIEBREAK_STRESS
      normal = 'NFLS'
      shear = 'SFLS'
      if (.not. card%bad) then
        option = int_field(f, 'OPTION')
        select case (option)
        case (2)
          if (real_field(f, 'CN') /= 0.0_wp) call card_warning(card, who//': CN ignored: '// &
              'the tie holds the nodes kinematically (no tie stiffness)')
        case (1, 3)
          call fail(who//': OPTION = '//itoa(option)//' (nodes that come into contact '// &
              'stick for good) is not supported: OPTION = 2 ties the nodes in contact at the '// &
              'start until NFLS/SFLS fail them (doc/keywords.md 3.10)')
        case (4)
          call fail(who//': OPTION = 4 (tied in the normal direction, sliding with '// &
              'friction) is not supported: OPTION = 2 ties the nodes in every direction '// &
              'until NFLS/SFLS fail them')
        case default
          call fail(who//': OPTION = '//itoa(option)//' is not supported: OPTION = 2 ties '// &
              'the nodes until NFLS/SFLS fail them (the damage and cohesive responses 5-14 '// &
              'and the negative ones are not computed)')
        end select
      end if
    end select
    if (card%bad) then
      bad = .true.
      return
    end if
    contact%fail_normal = real_field(f, normal)
    contact%fail_shear = real_field(f, shear)
    if (.not. contact%fail_normal > 0.0_wp) call fail(who//': field '//normal//' must be '// &
        '> 0 (the tensile failure '//trim(merge('force ', 'stress', normal == 'NFLF'))//', got '// &
        rtoa(contact%fail_normal)//'); a tie that never fails is *CONTACT_TIED_...')
    if (.not. contact%fail_shear > 0.0_wp) call fail(who//': field '//shear//' must be '// &
        '> 0 (the shear failure '//trim(merge('force ', 'stress', shear == 'SFLF'))//', got '// &
        rtoa(contact%fail_shear)//')')
    if (.not. (contact%fail_exponent_normal > 0.0_wp .and. &
               contact%fail_exponent_shear > 0.0_wp)) call fail(who//': fields NEN and MES '// &
        'must be > 0 (blank: 2)')
  contains
    !> Report and remember an error.
    subroutine fail(message)
      character(len=*), intent(in) :: message    !< what is wrong
      call card_error(card, message)
      bad = .true.
    end subroutine fail
  end subroutine read_tiebreak_card

  !> Values of cards 1-3 that mefem cannot honour or that make no sense.
  subroutine check_contact(card1, card2, card3, contact, nodes_a, transducer, who, saboxid, &
                           sbboxid, bad)
    type(card_t), intent(in) :: card1, card2, card3  !< the cards
    type(contact_t), intent(in) :: contact           !< the contact read
    logical, intent(in) :: nodes_a                   !< SURFA may be a node set (SURFATYP 4)
    logical, intent(in) :: transducer                !< a force transducer (SURFB 0)
    character(len=*), intent(in) :: who              !< 'contact 5'
    integer, intent(in) :: saboxid, sbboxid          !< box ids
    logical, intent(inout) :: bad                    !< set on any error
    if (contact%single_surface) then
      ! SURFA alone: all parts (SURFATYP 5), all but a part set (6), a part set, part or
      ! segment set; SURFB and SURFBTYP are not used by LS-DYNA either
      if (.not. any(contact%surf_a_type == [0, 2, 3, 5, 6])) call fail(card1, who// &
          ': field SURFATYP = '//itoa(contact%surf_a_type)//' is not supported '// &
          '(0 segment set, 2 part set, 3 part, 5 all parts, 6 all parts but a part set)')
      if (contact%surf_a_type /= 5 .and. contact%surf_a_id <= 0) call fail(card1, who// &
          ': field SURFA must be a positive id (got '//itoa(contact%surf_a_id)// &
          '); for all parts give SURFATYP = 5')
      if (contact%surf_b_id /= 0 .or. contact%surf_b_type /= 0) call card_warning(card1, &
          who//': SURFB and SURFBTYP are not used by a single-surface contact')
    else if (transducer) then
      ! the forces of all contacts on SURFA's nodes
      if (contact%surf_a_id <= 0) call fail(card1, who//': field SURFA must be a positive '// &
          'id (got '//itoa(contact%surf_a_id)//')')
      if (contact%surf_b_id /= 0) call fail(card1, who//': field SURFB = '// &
          itoa(contact%surf_b_id)//': mefem''s force transducer measures the forces of all '// &
          'contacts on SURFA; give SURFB 0 (or define the pair as its own contact, whose '// &
          'forces rcforc has)')
      if (.not. any(contact%surf_a_type == [0, 2, 3])) call fail(card1, who// &
          ': field SURFATYP = '//itoa(contact%surf_a_type)//' is not supported '// &
          '(0 segment set, 2 part set, 3 part)')
    else
      if (contact%surf_a_id <= 0 .or. contact%surf_b_id <= 0) call fail(card1, who// &
          ': fields SURFA and SURFB must be positive ids (got '//itoa(contact%surf_a_id)// &
          ' and '//itoa(contact%surf_b_id)//')')
      if (nodes_a) then
        if (.not. any(contact%surf_a_type == [0, 2, 3, 4])) call fail(card1, who// &
            ': field SURFATYP = '//itoa(contact%surf_a_type)//' is not supported '// &
            '(0 segment set, 2 part set, 3 part, 4 node set)')
      else if (.not. any(contact%surf_a_type == [0, 2, 3])) then
        call fail(card1, who//': field SURFATYP = '//itoa(contact%surf_a_type)//' is not '// &
            'supported (0 segment set, 2 part set, 3 part)')
      end if
      if (.not. any(contact%surf_b_type == [0, 2, 3])) call fail(card1, who// &
          ': field SURFBTYP = '//itoa(contact%surf_b_type)//' is not supported '// &
          '(0 segment set, 2 part set, 3 part)')
    end if
    if (saboxid /= 0 .or. sbboxid /= 0) call fail(card1, who// &
        ': fields SABOXID/SBBOXID: boxes (*DEFINE_BOX) are not supported')
    if (contact%fs < 0.0_wp .and. contact%fs /= FS_FROM_PARTS) call fail(card2, who// &
        ': field FS must not be negative, or -1 for the friction of the SURFA part''s '// &
        '*PART_CONTACT '//quoted_real(contact%fs))
    if (contact%fd < 0.0_wp) call fail(card2, who//': field FD must not be negative '// &
        quoted_real(contact%fd))
    if (contact%dc < 0.0_wp) call fail(card2, who//': field DC must not be negative '// &
        quoted_real(contact%dc))
    if (contact%birth >= contact%death) call fail(card2, who//': field BT ('// &
        rtoa(contact%birth)//') must be before DT ('//rtoa(contact%death)//')')
    if (contact%sfsa < 0.0_wp .or. contact%sfsb < 0.0_wp) call fail(card3, who// &
        ': fields SFSA/SFSB must be > 0 (got '//rtoa(contact%sfsa)//' and '// &
        rtoa(contact%sfsb)//')')
  contains
    !> Report and remember an error.
    subroutine fail(where_card, message)
      type(card_t), intent(in) :: where_card     !< the card with the field
      character(len=*), intent(in) :: message    !< what is wrong
      call card_error(where_card, message)
      bad = .true.
    end subroutine fail
  end subroutine check_contact

  !> Values of optional cards A-C.
  subroutine check_optional(card, k, contact, who, bad)
    type(card_t), intent(in) :: card                 !< optional card k
    integer, intent(in) :: k                         !< 1 = A, 2 = B, 3 = C
    type(contact_t), intent(in) :: contact           !< the contact read
    character(len=*), intent(in) :: who              !< 'contact 5'
    logical, intent(inout) :: bad                    !< set on any error
    select case (k)
    case (1)
      if (contact%soft < 0 .or. contact%soft > 2) then
        call card_error(card, who//': field SOFT must be 0, 1 or 2 (got '// &
            itoa(contact%soft)//')')
        bad = .true.
      else if (contact%sofscl < 0.0_wp) then
        call card_error(card, who//': field SOFSCL must be > 0 '//quoted_real(contact%sofscl))
        bad = .true.
      end if
    case (2)
      if (contact%penmax < 0.0_wp) then
        call card_error(card, who//': field PENMAX must not be negative '// &
            quoted_real(contact%penmax))
        bad = .true.
      end if
    case (3)
      if (contact%igap < 0 .or. contact%ignore < -2 .or. contact%ignore > 2) then
        call card_error(card, who//': fields IGAP >= 0 and IGNORE in -2..2 expected (got '// &
            itoa(contact%igap)//' and '//itoa(contact%ignore)//')')
        bad = .true.
      end if
    end select
  end subroutine check_optional

  !> *RIGIDWALL_PLANAR (option ID): NSID NSIDEX BOXID OFFSET BIRTH DEATH RWKSF /
  !> XT YT ZT XH YH ZH FRIC WVEL, repeated. NSID = 0: all nodes.
  subroutine read_rigidwall_planar(rd, options, model)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    character(len=*), parameter :: KEY = 'RIGIDWALL_PLANAR'
    type(rigid_wall_t) :: wall
    type(card_t) :: card, card2
    type(card_fields_t) :: f
    logical :: got, ok
    integer :: id
    character(len=80) :: heading
    id = 0
    call read_id_option(rd, options, id, heading, ok)
    if (.not. ok) return
    do
      call next_card(rd, card, got)
      if (.not. got) exit
      call read_layout_card(rd, card, KEY, 1, f)
      wall = rigid_wall_t()
      wall%id = id
      wall%node_set_id = int_field(f, 'NSID')
      wall%exempt_set_id = int_field(f, 'NSIDEX')
      wall%box_id = int_field(f, 'BOXID')
      wall%offset = real_field(f, 'OFFSET')
      wall%birth = real_field(f, 'BIRTH')
      wall%death = real_field(f, 'DEATH')
      wall%stiffness_scale = real_field(f, 'RWKSF')
      wall%src = source_t(card%file, card%line)
      call next_card(rd, card2, got, keep_blank=.true.)
      if (.not. got) then
        call card_error(card, 'missing card 2 (XT YT ZT XH YH ZH FRIC WVEL)')
        exit
      end if
      call read_layout_card(rd, card2, KEY, 2, f)
      wall%tail = [real_field(f, 'XT'), real_field(f, 'YT'), real_field(f, 'ZT')]
      wall%head = [real_field(f, 'XH'), real_field(f, 'YH'), real_field(f, 'ZH')]
      wall%friction = real_field(f, 'FRIC')
      wall%weld_velocity = real_field(f, 'WVEL')
      if (card%bad .or. card2%bad) cycle
      if (wall%node_set_id < 0 .or. wall%exempt_set_id < 0 .or. wall%box_id < 0) then
        call card_error(card, 'fields NSID/NSIDEX/BOXID must not be negative')
      else if (wall%birth >= wall%death) then
        call card_error(card, 'field BIRTH ('//rtoa(wall%birth)//') must be before DEATH ('// &
            rtoa(wall%death)//')')
      else if (wall%stiffness_scale < 0.0_wp) then
        call card_error(card, 'field RWKSF must be > 0 '//quoted_real(wall%stiffness_scale))
      else if (all(wall%head == wall%tail)) then
        call card_error(card2, 'the head (XH YH ZH) equals the tail (XT YT ZT): the wall '// &
            'normal is undefined')
      else if (wall%friction < 0.0_wp .or. wall%friction > 1.0_wp) then
        if (wall%friction == 2.0_wp .or. wall%friction == 3.0_wp) then
          call card_error(card2, 'field FRIC = '//rtoa(wall%friction)//' (welding) is not '// &
              'supported')
        else
          call card_error(card2, 'field FRIC must be between 0 and 1 '// &
              quoted_real(wall%friction))
        end if
      else
        call add_rigid_wall(model, wall)
      end if
    end do
  end subroutine read_rigidwall_planar

  !> *RIGIDWALL_GEOMETRIC_FLAT, _PRISM, _CYLINDER, _SPHERE (options MOTION, ID, DISPLAY): one
  !> wall per keyword. [ID card] / NSID NSIDEX BOXID BIRTH DEATH / XT YT ZT XH YH ZH FRIC /
  !> the shape's card (FLAT: XHEV YHEV ZHEV LENL LENM; PRISM: ... LENP; CYLINDER: RADCYL
  !> LENCYL NSEGS; SPHERE: RADSPH) / [MOTION: LCID OPT VX VY VZ] / [DISPLAY: PID RO E PR, not
  !> used]. A FLAT wall without edges (LENL = LENM = 0) is a plane, as *RIGIDWALL_PLANAR.
  subroutine read_rigidwall_geometric(rd, options, model, shape)
    type(reader_t), intent(inout) :: rd          !< reading state
    character(len=*), intent(in) :: options      !< keyword options
    type(model_t), intent(inout) :: model        !< model appended to
    integer, intent(in) :: shape                 !< WALL_FLAT, _PRISM, _CYLINDER, _SPHERE
    type(rigid_wall_t) :: wall
    character(len=*), parameter :: KEY = 'RIGIDWALL_GEOMETRIC_FLAT'   !< cards 1, 2, 4
    type(card_t) :: card, card2, card3, card4
    type(card_fields_t) :: f
    logical :: got, ok, bad
    character(len=80) :: heading
    character(len=:), allocatable :: who
    wall = rigid_wall_t()
    wall%shape = shape
    wall%keyword = trim(rd%keyword)
    call read_id_option(rd, options, wall%id, heading, ok)
    if (.not. ok) return
    who = 'rigid wall'
    if (wall%id /= 0) who = 'rigid wall '//itoa(wall%id)
    call next_card(rd, card, got, keep_blank=.true.)
    if (.not. got) then
      call keyword_error(rd, 'missing card 1 (NSID NSIDEX BOXID BIRTH DEATH)')
      return
    end if
    call read_layout_card(rd, card, KEY, 1, f)
    wall%node_set_id = int_field(f, 'NSID')
    wall%exempt_set_id = int_field(f, 'NSIDEX')
    wall%box_id = int_field(f, 'BOXID')
    wall%birth = real_field(f, 'BIRTH')
    wall%death = real_field(f, 'DEATH')
    wall%src = source_t(card%file, card%line)
    call next_card(rd, card2, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card, who//': missing card 2 (XT YT ZT XH YH ZH FRIC)')
      return
    end if
    call read_layout_card(rd, card2, KEY, 2, f)
    wall%tail = [real_field(f, 'XT'), real_field(f, 'YT'), real_field(f, 'ZT')]
    wall%head = [real_field(f, 'XH'), real_field(f, 'YH'), real_field(f, 'ZH')]
    wall%friction = real_field(f, 'FRIC')
    call next_card(rd, card3, got, keep_blank=.true.)
    if (.not. got) then
      call card_error(card2, who//': missing card 3 (the '//trim(shape_name(shape))// &
          ' wall''s dimensions)')
      return
    end if
    ! card 3 by shape: the layout of *RIGIDWALL_GEOMETRIC_FLAT, _PRISM, _CYLINDER, _SPHERE
    call read_layout_card(rd, card3, 'RIGIDWALL_GEOMETRIC_'//to_upper(trim(shape_name(shape))), &
                          3, f)
    select case (shape)
    case (WALL_FLAT, WALL_PRISM)
      wall%edge = [real_field(f, 'XHEV'), real_field(f, 'YHEV'), real_field(f, 'ZHEV')]
      wall%length_l = real_field(f, 'LENL')
      wall%length_m = real_field(f, 'LENM')
      if (shape == WALL_PRISM) wall%length_p = real_field(f, 'LENP')
    case (WALL_CYLINDER)
      wall%radius = real_field(f, 'RADCYL')              ! (NSEGS: for display, not used)
      wall%length = real_field(f, 'LENCYL')
    case (WALL_SPHERE)
      wall%radius = real_field(f, 'RADSPH')
    end select
    if (has_option(options, 'MOTION')) then
      call next_card(rd, card4, got, keep_blank=.true.)
      if (.not. got) then
        call card_error(card3, who//': missing the MOTION card (LCID OPT VX VY VZ)')
        return
      end if
      call read_layout_card(rd, card4, KEY, 4, f)
      wall%motion_curve_id = int_field(f, 'LCID')
      wall%motion_option = int_field(f, 'OPT')
      wall%motion_direction = [real_field(f, 'VX'), real_field(f, 'VY'), real_field(f, 'VZ')]
      if (.not. card4%bad) then
        if (.not. any(wall%motion_option == [0, 1])) then
          call card_error(card4, who//': field OPT must be 0 (LCID is the velocity) or 1 '// &
              '(the displacement) (got '//itoa(wall%motion_option)//')')
          card4%bad = .true.
        else if (.not. norm2(wall%motion_direction) > 0.0_wp) then
          call card_error(card4, who//': the direction VX VY VZ of the motion is zero')
          card4%bad = .true.
        else
          wall%motion_direction = wall%motion_direction/norm2(wall%motion_direction)
        end if
      end if
      if (card4%bad) return
    end if
    if (has_option(options, 'DISPLAY')) then
      call next_card(rd, card4, got, keep_blank=.true.)     ! PID RO E PR: for display only
    end if
    call reject_extra_cards(rd, who)
    if (card%bad .or. card2%bad .or. card3%bad) return
    bad = .false.
    if (wall%node_set_id < 0 .or. wall%exempt_set_id < 0 .or. wall%box_id < 0) &
        call fail(card, who//': fields NSID/NSIDEX/BOXID must not be negative')
    if (wall%birth >= wall%death) call fail(card, who//': field BIRTH ('//rtoa(wall%birth)// &
        ') must be before DEATH ('//rtoa(wall%death)//')')
    if (shape /= WALL_SPHERE .and. all(wall%head == wall%tail)) call fail(card2, who// &
        ': the head (XH YH ZH) equals the tail (XT YT ZT): the wall''s axis is undefined')
    if (wall%friction < 0.0_wp .or. wall%friction > 1.0_wp) call fail(card2, who// &
        ': field FRIC must be between 0 and 1 '//quoted_real(wall%friction))
    select case (shape)
    case (WALL_FLAT, WALL_PRISM)
      if (wall%length_l < 0.0_wp .or. wall%length_m < 0.0_wp .or. wall%length_p < 0.0_wp) &
        call fail(card3, who//': the edge lengths must not be negative')
      if (shape == WALL_PRISM .and. .not. (wall%length_l > 0.0_wp .and. wall%length_m > &
          0.0_wp .and. wall%length_p > 0.0_wp)) call fail(card3, who//': a prism needs '// &
          'LENL, LENM and LENP > 0')
      if (wall%length_l > 0.0_wp .or. wall%length_m > 0.0_wp) then
        if (any(wall%head /= wall%tail)) then          ! (else reported above)
          if (norm2(wall%edge - dot_product(wall%edge, axis(wall))*axis(wall)) <= &
              1.0e-12_wp*norm2(wall%edge) .or. all(wall%edge == 0.0_wp)) call fail(card3, &
              who//': XHEV YHEV ZHEV must not be zero or along the wall''s normal (it gives '// &
              'the direction of the l edge)')
        end if
      end if
      if (shape == WALL_FLAT .and. wall%length_l == 0.0_wp .and. wall%length_m == 0.0_wp) &
        wall%shape = WALL_PLANE
    case (WALL_CYLINDER, WALL_SPHERE)
      if (.not. wall%radius > 0.0_wp) call fail(card3, who//': the radius must be > 0 '// &
          quoted_real(wall%radius))
      if (wall%length < 0.0_wp) call fail(card3, who//': field LENCYL must not be negative')
    end select
    if (.not. bad) call add_rigid_wall(model, wall)
  contains
    !> Report an error and remember it.
    subroutine fail(where_card, message)
      type(card_t), intent(in) :: where_card     !< the card with the field
      character(len=*), intent(in) :: message    !< what is wrong
      call card_error(where_card, message)
      bad = .true.
    end subroutine fail
    !> Unit vector from the tail to the head.
    function axis(w) result(n)
      type(rigid_wall_t), intent(in) :: w        !< the wall
      real(wp) :: n(3)
      n = (w%head - w%tail)/norm2(w%head - w%tail)
    end function axis
  end subroutine read_rigidwall_geometric

  !> 'flat', 'prism', 'cylinder' or 'sphere'.
  pure function shape_name(shape) result(name)
    integer, intent(in) :: shape                 !< WALL_*
    character(len=8) :: name
    select case (shape)
    case (WALL_PRISM)
      name = 'prism'
    case (WALL_CYLINDER)
      name = 'cylinder'
    case (WALL_SPHERE)
      name = 'sphere'
    case default
      name = 'flat'
    end select
  end function shape_name

  !> Return the card just read to the deck (it belongs to the next reader).
  subroutine push_back_card(rd)
    type(reader_t), intent(inout) :: rd          !< reading state
    call deck_push_back(rd%deck)
  end subroutine push_back_card

  !> Append a contact.
  subroutine add_contact(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(contact_t), intent(in) :: item        !< the record
    type(contact_t), allocatable :: grown(:)
    if (.not. allocated(model%contacts)) allocate(model%contacts(0))
    if (model%n_contacts == size(model%contacts)) then
      allocate(grown(max(8, 2*model%n_contacts)))
      grown(1:model%n_contacts) = model%contacts(1:model%n_contacts)
      call move_alloc(grown, model%contacts)
    end if
    model%n_contacts = model%n_contacts + 1
    model%contacts(model%n_contacts) = item
  end subroutine add_contact

  !> Append a tied contact.
  subroutine add_tie(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(contact_t), intent(in) :: item        !< the record
    type(contact_t), allocatable :: grown(:)
    if (.not. allocated(model%ties)) allocate(model%ties(0))
    if (model%n_ties == size(model%ties)) then
      allocate(grown(max(8, 2*model%n_ties)))
      grown(1:model%n_ties) = model%ties(1:model%n_ties)
      call move_alloc(grown, model%ties)
    end if
    model%n_ties = model%n_ties + 1
    model%ties(model%n_ties) = item
  end subroutine add_tie

  !> Append a force transducer.
  subroutine add_transducer(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(contact_t), intent(in) :: item        !< the record
    type(contact_t), allocatable :: grown(:)
    if (.not. allocated(model%transducers)) allocate(model%transducers(0))
    if (model%n_transducers == size(model%transducers)) then
      allocate(grown(max(8, 2*model%n_transducers)))
      grown(1:model%n_transducers) = model%transducers(1:model%n_transducers)
      call move_alloc(grown, model%transducers)
    end if
    model%n_transducers = model%n_transducers + 1
    model%transducers(model%n_transducers) = item
  end subroutine add_transducer

  !> Append a rigid wall.
  subroutine add_rigid_wall(model, item)
    type(model_t), intent(inout) :: model      !< model appended to
    type(rigid_wall_t), intent(in) :: item     !< the record
    type(rigid_wall_t), allocatable :: grown(:)
    if (.not. allocated(model%rigid_walls)) allocate(model%rigid_walls(0))
    if (model%n_rigid_walls == size(model%rigid_walls)) then
      allocate(grown(max(8, 2*model%n_rigid_walls)))
      grown(1:model%n_rigid_walls) = model%rigid_walls(1:model%n_rigid_walls)
      call move_alloc(grown, model%rigid_walls)
    end if
    model%n_rigid_walls = model%n_rigid_walls + 1
    model%rigid_walls(model%n_rigid_walls) = item
  end subroutine add_rigid_wall

end module mefem_read_contact
