!> Unit tests of the keyword reader core: number formats, fixed/free/long fields,
!> parameters, *INCLUDE, *END, comments, both *ELEMENT_SOLID layouts, error counting.
program test_reader_core
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal
  use mefem_numbers, only: parse_real, parse_int
  use mefem_errors, only: input_error_count, reset_input_errors
  use mefem_file_system, only: make_directory
  use mefem_model, only: model_t
  use mefem_keyword_reader, only: read_deck
  implicit none

  character(len=*), parameter :: DIR = '../out/reader_unit'
  logical :: ok

  call test_start('reader_core')
  call make_directory(DIR//'/sub', ok)
  call check(ok, 'output directory created')
  call test_numbers()
  call test_fixed_free_long()
  call test_include_and_end()
  call test_element_layouts()
  call test_errors_counted()
  call test_finish()

contains

  !> One real parse against its expected value.
  subroutine expect_real(text, want)
    character(len=*), intent(in) :: text
    real(wp), intent(in) :: want
    real(wp) :: x
    logical :: good
    call parse_real(text, x, good)
    call check(good, 'parse_real accepts "'//text//'"')
    call check_close(x, want, 0.0_wp, 'parse_real "'//text//'" exact value')
  end subroutine expect_real

  !> One real parse that must fail.
  subroutine reject_real(text)
    character(len=*), intent(in) :: text
    real(wp) :: x
    logical :: good
    call parse_real(text, x, good)
    call check(.not. good, 'parse_real rejects "'//text//'"')
  end subroutine reject_real

  subroutine test_numbers()
    integer :: k
    logical :: good
    real(wp) :: x
    call expect_real('1', 1.0_wp)
    call expect_real('-1.5', -1.5_wp)
    call expect_real('.5', 0.5_wp)
    call expect_real('2.', 2.0_wp)
    call expect_real('+3.25', 3.25_wp)
    call expect_real('1.0E+05', 1.0e5_wp)
    call expect_real('1e5', 1.0e5_wp)
    call expect_real('1.0D-3', 1.0e-3_wp)
    call expect_real('8.9-3', 8.9e-3_wp)
    call expect_real('8.90000-3', 8.9e-3_wp)
    call expect_real('1.0+5', 1.0e5_wp)
    call expect_real('5.000000E8', 5.0e8_wp)
    call expect_real('0.1', 0.1_wp)
    call expect_real('2.1e5', 2.1e5_wp)
    call expect_real('7.85e-9', 7.85e-9_wp)
    call expect_real('0.0', 0.0_wp)
    call expect_real('1.23456789012345678901234', 1.23456789012345678901234_wp)
    call expect_real('1e-300', 1.0e-300_wp)
    call reject_real('abc')
    call reject_real('1.2.3')
    call reject_real('e5')
    call reject_real('1e')
    call reject_real('--1')
    call reject_real('1.0-')
    call reject_real('1 0')
    call reject_real('1e999')
    call reject_real('.')
    call parse_real('', x, good)
    call check(.not. good, 'parse_real rejects empty text')
    call parse_int('12', k, good)
    call check(good .and. k == 12, 'parse_int "12"')
    call parse_int('-3', k, good)
    call check(good .and. k == -3, 'parse_int "-3"')
    call parse_int('3.', k, good)
    call check(good .and. k == 3, 'parse_int accepts integral real "3."')
    call parse_int('1e3', k, good)
    call check(good .and. k == 1000, 'parse_int accepts integral real "1e3"')
    call parse_int('3.5', k, good)
    call check(.not. good, 'parse_int rejects "3.5"')
    call parse_int('x1', k, good)
    call check(.not. good, 'parse_int rejects "x1"')
    call parse_int('99999999999', k, good)
    call check(.not. good, 'parse_int rejects out-of-range "99999999999"')
  end subroutine test_numbers

  !> Write lines to a file.
  subroutine write_file(path, lines)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: lines(:)
    integer :: u, i
    open(newunit=u, file=path, status='replace', action='write')
    do i = 1, size(lines)
      write(u, '(a)') trim(lines(i))
    end do
    close(u)
  end subroutine write_file

  subroutine test_fixed_free_long()
    type(model_t) :: model
    integer :: n_errors
    call reset_input_errors()
    call write_file(DIR//'/fields.k', [character(len=120) :: &
      '$ comment line', &
      '*keyword', &
      '*PARAMETER', &
      'R zval    2.5       I nid     7', &
      '*node', &
      '$#   nid               x               y               z      tc      rc', &
      '       1-1.000000000E+001.2345678900E+01           8.9-3       0       0', &
      '2,1.5,,3.0', &
      '    &nid           1.0+1          -&zval             0.0', &
      '*NODE +', &
      '                   3                 1.0                 2.0                 3.0', &
      '*node  some trailing words', &
      '       4             0.0             0.0             0.0       7', &
      '*END', &
      '*NODE', &
      '       5             9.0             9.0             9.0'])
    call read_deck(DIR//'/fields.k', model, n_errors)
    call check_equal(n_errors, 0, 'fields deck: no errors')
    call check_equal(model%nodes%n, 5, 'fields deck: nodes before *END read, none after')
    if (model%nodes%n < 5) return
    call check_equal(model%nodes%id(1), 1, 'node 1 id')
    call check_close(model%nodes%x(:, 1), [-1.0_wp, 12.3456789_wp, 8.9e-3_wp], 1.0e-15_wp, &
        'touching 16-wide fields and compact exponent')
    call check_close(model%nodes%x(:, 2), [1.5_wp, 0.0_wp, 3.0_wp], 0.0_wp, &
        'free format with an empty entry = default')
    call check_equal(model%nodes%id(3), 7, 'integer parameter &nid')
    call check_close(model%nodes%x(:, 3), [10.0_wp, -2.5_wp, 0.0_wp], 0.0_wp, &
        'negated real parameter -&zval')
    call check_equal(model%nodes%id(4), 3, '*NODE + long format id')
    call check_close(model%nodes%x(:, 4), [1.0_wp, 2.0_wp, 3.0_wp], 0.0_wp, &
        '*NODE + long format coordinates')
    call check_equal(model%nodes%tc(5), 7, 'trailing text after keyword name tolerated; TC read')
  end subroutine test_fixed_free_long

  subroutine test_include_and_end()
    type(model_t) :: model
    integer :: n_errors
    call reset_input_errors()
    call write_file(DIR//'/sub/inner.k', [character(len=80) :: &
      '*NODE', &
      '      20             2.0             0.0             0.0', &
      '*END', &
      '*NODE', &
      '      99             9.0             9.0             9.0'])
    call write_file(DIR//'/sub/middle.k', [character(len=80) :: &
      '*INCLUDE', &
      'inner.k', &
      '*NODE', &
      '      21             3.0             0.0             0.0'])
    call write_file(DIR//'/main_inc.k', [character(len=80) :: &
      '*KEYWORD', &
      '*NODE', &
      '      10             1.0             0.0             0.0', &
      '*INCLUDE', &
      'sub/middle.k', &
      '*NODE', &
      '      30             4.0             0.0             0.0'])
    call read_deck(DIR//'/main_inc.k', model, n_errors)
    call check_equal(n_errors, 0, 'nested include: no errors')
    call check_equal(model%nodes%n, 4, 'nested include: 4 nodes (inner *END stops inner only)')
    if (model%nodes%n == 4) call check(all(model%nodes%id(1:4) == [10, 20, 21, 30]), &
        'nested include: deck order kept, relative paths resolved per including file')
    ! recursion and missing files are errors
    call reset_input_errors()
    call write_file(DIR//'/loop.k', [character(len=80) :: '*KEYWORD', '*INCLUDE', 'loop.k'])
    call read_deck(DIR//'/loop.k', model, n_errors)
    call check_equal(n_errors, 1, 'recursive include reported once')
    call reset_input_errors()
    call write_file(DIR//'/missing.k', [character(len=80) :: '*KEYWORD', '*INCLUDE', &
        'nowhere.k', '*INCLUDE', 'nowhere2.k'])
    call read_deck(DIR//'/missing.k', model, n_errors)
    call check_equal(n_errors, 2, 'two missing includes: both reported')
  end subroutine test_include_and_end

  subroutine test_element_layouts()
    type(model_t) :: model
    integer :: n_errors
    call reset_input_errors()
    call write_file(DIR//'/elements.k', [character(len=100) :: &
      '*KEYWORD', &
      '*ELEMENT_SOLID', &
      '       1       1', &
      '       1       2       3       4       4       4       4       4', &
      '       2       1       1       2       3       4       4       4       4       4', &
      '       3       1       1       2       3       4', &
      '4,1', &
      '1,2,3,4,5,6,7,8', &
      '5,1,1,2,3,4', &
      '*ELEMENT_SHELL', &
      '       7       2       1       2       3', &
      '       8       2       1       2       3       4'])
    call read_deck(DIR//'/elements.k', model, n_errors)
    call check_equal(n_errors, 0, 'element layouts: no errors')
    call check_equal(model%elements%n, 7, 'element layouts: 7 elements')
    if (model%elements%n /= 7) return
    call check(all(model%elements%node_ids(:, 1) == [1, 2, 3, 4, 4, 4, 4, 4]), &
        'two-line layout')
    call check(all(model%elements%node_ids(:, 2) == [1, 2, 3, 4, 4, 4, 4, 4]), &
        'one-line legacy layout')
    call check(all(model%elements%node_ids(:, 3) == [1, 2, 3, 4, 4, 4, 4, 4]), &
        'tet as 6 fields: N5-N8 repeat N4')
    call check(all(model%elements%node_ids(:, 4) == [1, 2, 3, 4, 5, 6, 7, 8]), &
        'free-format two-line hex')
    call check(all(model%elements%node_ids(:, 5) == [1, 2, 3, 4, 4, 4, 4, 4]), &
        'free-format one-line tet')
    call check(all(model%elements%node_ids(1:4, 6) == [1, 2, 3, 3]), 'shell triangle N4 = N3')
    call check(all(model%elements%node_ids(1:4, 7) == [1, 2, 3, 4]), 'shell quad')
  end subroutine test_element_layouts

  subroutine test_errors_counted()
    type(model_t) :: model
    integer :: n_errors
    call reset_input_errors()
    call write_file(DIR//'/bad.k', [character(len=100) :: &
      '*KEYWORD', &
      '*NODE', &
      '       1             abc             0.0             0.0', &
      '       2             1.0             0.0        1.0.0', &
      '       x             1.0             0.0             0.0', &
      '      -4             1.0             0.0             0.0', &
      '       5             1.0             0.0             0.0       9', &
      '     &undefined      1.0             0.0             0.0', &
      '       6'//achar(9)//'1.0', &
      '*ELEMENT_SOLID', &
      '       1       1       1       2'])
    call read_deck(DIR//'/bad.k', model, n_errors)
    call check_equal(n_errors, 9, 'every bad card reported in one pass')
    call check_equal(model%nodes%n, 0, 'bad node cards are not stored')
    call reset_input_errors()
  end subroutine test_errors_counted

end program test_reader_core
