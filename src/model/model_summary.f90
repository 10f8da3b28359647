!> The run log's description of the model: counts, extent, parts with their element
!> formulation, material and mass, and the analysis controls, so users see what mefem
!> understood (a mass or an extent a factor 1000 off shows a unit slip).
module mefem_model_summary
  use mefem_kinds, only: wp
  use mefem_errors, only: say, warn
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t, material_t, MAT_RIGID, MAT_MOONEY_RIVLIN
  use mefem_model_resolve, only: formulation_name, element_mass
  use mefem_read_materials, only: material_keyword
  implicit none
  private

  public :: print_model_summary, deck_stem, unit_systems_fitting

  !> The consistent unit systems of LS-DYNA decks, as factors to SI: length (m), time (s),
  !> density (kg/m^3) and stress (Pa) of one deck unit. A material's density and modulus
  !> fit a system when they give a density and an elastic wave speed sqrt(E/rho) of real
  !> solids there (units_check).
  integer, parameter :: N_SYSTEMS = 6
  character(len=24), parameter :: SYSTEM_NAME(N_SYSTEMS) = [character(len=24) :: &
      'm, kg, s, Pa', 'mm, t, s, MPa', 'mm, kg, ms, GPa', 'mm, g, ms, MPa', &
      'cm, g, us, Mbar', 'in, lbf s2/in, s, psi']
  real(wp), parameter :: SYSTEM_DENSITY(N_SYSTEMS) = [1.0_wp, 1.0e12_wp, 1.0e9_wp, 1.0e6_wp, &
      1.0e3_wp, 1.0687e7_wp]
  real(wp), parameter :: SYSTEM_STRESS(N_SYSTEMS) = [1.0_wp, 1.0e6_wp, 1.0e9_wp, 1.0e6_wp, &
      1.0e11_wp, 6894.76_wp]
  !> Densities (kg/m^3) and elastic wave speeds (m/s) of real solids: foams to tungsten, soft
  !> rubber to diamond
  real(wp), parameter :: DENSITY_RANGE(2) = [10.0_wp, 3.0e4_wp]
  real(wp), parameter :: WAVE_SPEED_RANGE(2) = [5.0_wp, 2.0e4_wp]

contains

  !> Print the model summary on rank 0.
  subroutine print_model_summary(model, read_seconds, memory_mib)
    type(model_t), intent(in) :: model     !< resolved model
    real(wp), intent(in) :: read_seconds   !< wall time spent reading and checking
    real(wp), intent(in) :: memory_mib     !< peak memory so far (MiB)
    integer :: p, count_p
    real(wp) :: mass(model%n_parts), extent(3)
    character(len=:), allocatable :: line
    call say('model: '//itoa(model%nodes%n)//' nodes, '//itoa(model%elements%n)// &
             ' elements, '//itoa(model%n_parts)//' parts, '//itoa(model%dimension)//'D'// &
             merge(' (plane strain)', '               ', model%dimension == 2))
    if (model%nodes%n > 0) then
      extent = maxval(model%nodes%x(:, 1:model%nodes%n), dim=2) - &
               minval(model%nodes%x(:, 1:model%nodes%n), dim=2)
      call say('  extent '//rtoa(extent(1))//' x '//rtoa(extent(2))//' x '// &
               rtoa(extent(3))//' (length units of the deck)')
    end if
    mass = part_masses(model)
    do p = 1, model%n_parts
      count_p = count(model%elements%part(1:model%elements%n) == p)
      line = '  part '//itoa(model%parts(p)%id)//': '//itoa(count_p)//' elements, '// &
             formulation_name(model, p)
      if (model%parts(p)%material > 0) line = line//', '// &
          material_keyword(model%materials(model%parts(p)%material)%kind)// &
          ' (material '//itoa(model%parts(p)%material_id)//'), mass '//rtoa(mass(p))
      if (len_trim(model%parts(p)%title) > 0) line = line//' "'//trim(model%parts(p)%title)//'"'
      call say(line)
      if (count_p == 0) call warn('part '//itoa(model%parts(p)%id)//' has no elements (a '// &
          'mesh file missing from the *INCLUDE list, or an element card with the wrong PID?)')
    end do
    line = '  total mass '//rtoa(sum(mass))//' (density x volume in the deck''s units'
    if (model%dimension == 2) line = line//', per unit thickness'
    call say(line//')')
    if (allocated(model%nodes%added_mass)) then
      if (any(model%nodes%added_mass > 0.0_wp)) call say('  added mass (*ELEMENT_MASS, '// &
          '*ELEMENT_MASS_PART) '//rtoa(sum(model%nodes%added_mass))//' at '// &
          itoa(count(model%nodes%added_mass > 0.0_wp))//' nodes')
    end if
    call units_check(model)
    if (model%controls%have_termination) call say('  end time '// &
        rtoa(model%controls%end_time))
    call say('deck read and checked in '//rtoa(read_seconds)//' s, peak memory '// &
             rtoa(memory_mib)//' MiB per rank')
  end subroutine print_model_summary

  !> The unit systems the deformable materials' densities and moduli fit together (every
  !> material must fit a system to count it): said on the log; a material that fits none is
  !> warned, with its density and wave speed in the deck's units (SI density with MPa, say,
  !> gives a wave speed of 5 deck units: "det F <= 0" at the first cycle otherwise).
  subroutine units_check(model)
    type(model_t), intent(in) :: model     !< resolved model
    logical :: fits(N_SYSTEMS), any_material
    character(len=:), allocatable :: names
    integer :: m, k
    fits = .true.
    any_material = .false.
    do m = 1, model%n_materials
      associate (mat => model%materials(m))
        if (mat%kind == MAT_RIGID .or. .not. (mat%density > 0.0_wp .and. &
            material_modulus(mat) > 0.0_wp)) cycle
        any_material = .true.
        if (.not. any(unit_systems_fitting(mat%density, material_modulus(mat)))) then
          call warn('material '//itoa(mat%id)//': density '//rtoa(mat%density)// &
              ' and modulus '//rtoa(material_modulus(mat))//' fit none of the consistent '// &
              'unit systems ('//all_system_names()//'): their wave speed sqrt(E/rho) is '// &
              rtoa(sqrt(material_modulus(mat)/mat%density))//' length units per time unit; '// &
              'check that density, modulus and lengths are in one system (SI density with '// &
              'MPa moduli is a common slip)')
        end if
        fits = fits .and. unit_systems_fitting(mat%density, material_modulus(mat))
      end associate
    end do
    if (.not. any_material .or. .not. any(fits)) return
    names = ''
    do k = 1, N_SYSTEMS
      if (fits(k)) names = names//merge('; ', '  ', len(names) > 0)//trim(SYSTEM_NAME(k))
    end do
    call say('  units: the materials fit '//trim(adjustl(names)))
  end subroutine units_check

  !> Which unit systems a density and a modulus (deck units) fit: a real solid's density and
  !> wave speed once converted to SI.
  pure function unit_systems_fitting(density, modulus) result(fits)
    real(wp), intent(in) :: density, modulus   !< in the deck's units
    logical :: fits(N_SYSTEMS)
    real(wp) :: rho, speed
    integer :: k
    do k = 1, N_SYSTEMS
      rho = density*SYSTEM_DENSITY(k)
      speed = sqrt(modulus*SYSTEM_STRESS(k)/rho)
      fits(k) = rho >= DENSITY_RANGE(1) .and. rho <= DENSITY_RANGE(2) .and. &
                speed >= WAVE_SPEED_RANGE(1) .and. speed <= WAVE_SPEED_RANGE(2)
    end do
  end function unit_systems_fitting

  !> The stiffness a material's waves travel with: E (Mooney-Rivlin: 6 (A + B), three times
  !> its small-strain shear modulus 2 (A + B)).
  pure real(wp) function material_modulus(mat)
    type(material_t), intent(in) :: mat    !< the material
    material_modulus = mat%young
    if (mat%kind == MAT_MOONEY_RIVLIN) material_modulus = 6.0_wp*(mat%mr_a + mat%mr_b)
  end function material_modulus

  !> The names of the unit systems, for messages.
  function all_system_names() result(names)
    character(len=:), allocatable :: names
    integer :: k
    names = trim(SYSTEM_NAME(1))
    do k = 2, N_SYSTEMS
      names = names//'; '//trim(SYSTEM_NAME(k))
    end do
  end function all_system_names

  !> Mass of each part: density times the elements' volume (element_mass).
  function part_masses(model) result(mass)
    type(model_t), intent(in) :: model     !< resolved model
    real(wp) :: mass(model%n_parts)
    integer :: e, p
    mass = 0.0_wp
    do e = 1, model%elements%n
      p = model%elements%part(e)
      if (p > 0) mass(p) = mass(p) + element_mass(model, e)
    end do
  end function part_masses

  !> File name of a deck without directory and extension ("input/a.k" -> "a").
  function deck_stem(path) result(s)
    character(len=*), intent(in) :: path   !< deck path
    character(len=:), allocatable :: s
    integer :: slash, dot
    slash = index(path, '/', back=.true.)
    s = path(slash+1:)
    dot = index(s, '.', back=.true.)
    if (dot > 1) s = s(1:dot-1)
  end function deck_stem

end module mefem_model_summary
