!> The line source of a keyword deck: files, *INCLUDE, *END, comments, file:line tracking.
!>
!> A deck is read as a stream of lines. Each file is loaded whole into memory (one read,
!> fast for decks of millions of lines) and split at line feeds; carriage returns are dropped.
!> The source resolves `*INCLUDE` (paths relative to the including file, then the
!> `*INCLUDE_PATH` directories; nested; recursion and missing files are errors) and `*END`
!> (ends the current file), skips `$` comments, and hands everything else to the keyword
!> reader together with its file index and line number. File names are kept in a table so
!> that any later message can say `file:line`.
module mefem_deck_source
  use mefem_kinds, only: i8
  use mefem_errors, only: input_error
  use mefem_strings, only: to_upper, itoa, dirname, join_path, is_absolute_path
  use mefem_file_system, only: canonical_path
  implicit none
  private

  integer, parameter, public :: MAX_LINE = 2048       !< longest line accepted, in characters
  integer, parameter :: MAX_DEPTH = 32                !< deepest *INCLUDE nesting
  integer, parameter :: MAX_GARBAGE = 1               !< binary-data messages per file

  public :: deck_open, deck_next_line, deck_push_back, deck_close
  public :: file_name, location
  public :: LINE_KEYWORD, LINE_DATA, LINE_BLANK, LINE_EOF

  integer, parameter :: LINE_KEYWORD = 1, LINE_DATA = 2, LINE_BLANK = 3, LINE_EOF = 4

  !> One open file of the include stack.
  type :: open_file_t
    character(len=:), allocatable :: buf   !< the whole file
    integer(i8) :: pos = 1                 !< next byte to read
    integer :: line = 0                    !< number of the line last read
    integer :: file = 0                    !< index in the file-name table
    integer :: garbage = 0                 !< binary-data messages given
    logical :: include_list = .false.      !< in an *INCLUDE whose next data lines name more
                                           !< files (LS-DYNA: one file name per card)
  end type open_file_t

  !> A deck being read: the include stack and the current line.
  type, public :: deck_t
    type(open_file_t) :: stack(MAX_DEPTH)
    integer :: depth = 0                   !< files open (0 = finished)
    character(len=MAX_LINE) :: text = ''   !< current line (valid in 1:length)
    integer :: length = 0                  !< characters in the current line
    integer :: kind = LINE_EOF             !< LINE_* class of the current line
    integer :: file = 0                    !< file index of the current line
    integer :: line = 0                    !< line number of the current line
    logical :: pushed_back = .false.       !< the current line is to be returned again
    logical :: reprocess = .false.         !< the current line is a keyword still to be handled
    integer :: n_paths = 0                 !< *INCLUDE_PATH directories
    character(len=512) :: paths(64) = ''
  end type deck_t

  !> Name table of every file opened in this run.
  type :: name_t
    character(len=:), allocatable :: s
  end type name_t
  type(name_t), allocatable :: names(:)
  integer :: n_names = 0

contains

  !> Open the main deck file. ok is false (after a message) when it cannot be read.
  subroutine deck_open(deck, path, ok)
    type(deck_t), intent(out) :: deck   !< the deck source
    character(len=*), intent(in) :: path  !< path of the main deck
    logical, intent(out) :: ok            !< true when the file was opened
    call push_file(deck, path, '', ok)
  end subroutine deck_open

  !> Release all open files.
  subroutine deck_close(deck)
    type(deck_t), intent(inout) :: deck   !< the deck source
    integer :: k
    do k = 1, deck%depth
      if (allocated(deck%stack(k)%buf)) deallocate(deck%stack(k)%buf)
    end do
    deck%depth = 0
  end subroutine deck_close

  !> Name of file number i, as opened (relative to the working directory or absolute).
  function file_name(i) result(s)
    integer, intent(in) :: i   !< file index
    character(len=:), allocatable :: s
    if (i >= 1 .and. i <= n_names) then
      s = names(i)%s
    else
      s = '(no file)'
    end if
  end function file_name

  !> "file:line" text of a location.
  function location(file, line) result(s)
    integer, intent(in) :: file, line   !< file index and line number
    character(len=:), allocatable :: s
    s = file_name(file)//':'//itoa(line)
  end function location

  !> Return the current line again at the next deck_next_line call.
  subroutine deck_push_back(deck)
    type(deck_t), intent(inout) :: deck   !< the deck source
    deck%pushed_back = .true.
  end subroutine deck_push_back

  !> Advance to the next line that is not a comment, resolving *INCLUDE and *END.
  !> On return deck%kind is LINE_KEYWORD, LINE_DATA, LINE_BLANK or LINE_EOF.
  subroutine deck_next_line(deck)
    type(deck_t), intent(inout) :: deck   !< the deck source
    character(len=32) :: head
    if (deck%pushed_back) then
      deck%pushed_back = .false.
      return
    end if
    do
      if (deck%reprocess) then
        deck%reprocess = .false.
      else
        call read_raw_line(deck)
      end if
      ! after an included file: more file names of the same *INCLUDE, until a keyword
      if (deck%depth > 0 .and. deck%kind /= LINE_EOF) then
        if (deck%stack(deck%depth)%include_list) then
          if (deck%kind == LINE_BLANK) cycle
          if (deck%kind == LINE_DATA) then
            call include_named_file(deck)
            cycle
          end if
          deck%stack(deck%depth)%include_list = .false.
        end if
      end if
      if (deck%kind /= LINE_KEYWORD) return
      head = keyword_head(deck%text(1:deck%length))
      if (head == '*END') then
        call pop_file(deck)
        cycle
      else if (head == '*INCLUDE' .or. head == '*INCLUDE_PATH' .or. &
               head == '*INCLUDE_PATH_RELATIVE') then
        call handle_include(deck, head)
        cycle
      end if
      return
    end do
  end subroutine deck_next_line

  !> Upper-case keyword name of a keyword line, without options text after blanks.
  pure function keyword_head(line) result(head)
    character(len=*), intent(in) :: line   !< a line starting with '*'
    character(len=32) :: head
    integer :: k
    k = scan(line, ' ,')
    if (k == 0) k = len(line) + 1
    head = to_upper(line(1:min(k-1, 32)))
  end function keyword_head

  !> Read the next physical line into deck%text, popping finished files; skip comments.
  subroutine read_raw_line(deck)
    type(deck_t), intent(inout) :: deck   !< the deck source
    integer(i8) :: nl, start, n
    integer :: bad
    do
      if (deck%depth == 0) then
        deck%kind = LINE_EOF
        deck%length = 0
        return
      end if
      associate (f => deck%stack(deck%depth))
        if (f%pos > len(f%buf, kind=i8)) then
          call pop_file(deck)
          cycle
        end if
        start = f%pos
        nl = newline_offset(f%buf, start)
        if (nl == 0) then
          n = len(f%buf, kind=i8) - start + 1
          f%pos = len(f%buf, kind=i8) + 1
        else
          n = nl - 1
          f%pos = start + nl
        end if
        f%line = f%line + 1
        deck%file = f%file
        deck%line = f%line
        if (n > 0) then
          if (f%buf(start+n-1:start+n-1) == achar(13)) n = n - 1
        end if
        if (n > 0) then
          if (f%buf(start:start) == '$') cycle
        end if
        bad = first_binary_byte(f%buf(start:start+n-1))
        if (bad > 0) then
          if (f%garbage < MAX_GARBAGE) call input_error(location(f%file, f%line), &
              'binary data (byte '//itoa(iachar(f%buf(start+bad-1:start+bad-1)))// &
              ' at column '//itoa(bad)//'): this is not a text keyword deck; rest of file skipped')
          f%garbage = f%garbage + 1
          call pop_file(deck)
          cycle
        end if
        if (n > MAX_LINE) then
          call input_error(location(f%file, f%line), 'line of '//itoa(int(n))// &
              ' characters is longer than the '//itoa(MAX_LINE)//' accepted; line skipped')
          cycle
        end if
        deck%length = int(n)
        if (n > 0) deck%text(1:n) = f%buf(start:start+n-1)
      end associate
      exit
    end do
    if (deck%length == 0) then
      deck%kind = LINE_BLANK
    else if (deck%text(1:1) == '*') then
      deck%kind = LINE_KEYWORD
    else if (len_trim(deck%text(1:deck%length)) == 0) then
      deck%kind = LINE_BLANK
    else
      deck%kind = LINE_DATA
    end if
  end subroutine read_raw_line

  !> Offset from start of the first line feed in buf(start:), 1 for buf(start:start), 0 when
  !> there is none: index(buf(start:), achar(10)) as a plain loop (the library's general
  !> substring search costs several times more per byte).
  pure integer(i8) function newline_offset(buf, start)
    character(len=*), intent(in) :: buf   !< the whole file
    integer(i8), intent(in) :: start      !< where the line starts
    integer(i8) :: k
    newline_offset = 0
    do k = start, len(buf, kind=i8)
      if (iachar(buf(k:k)) == 10) then
        newline_offset = k - start + 1
        return
      end if
    end do
  end function newline_offset

  !> Position of the first byte that cannot be in a text deck (0 if none). Tabs, and bytes
  !> above 127 (accented letters in titles), are text.
  pure integer function first_binary_byte(s)
    character(len=*), intent(in) :: s   !< one line
    integer :: i, c, n_control
    first_binary_byte = 0
    ! a branch-free count first (vectorised by the compiler): lines are nearly always clean
    n_control = 0
    do i = 1, len(s)
      c = iachar(s(i:i))
      n_control = n_control + merge(1, 0, c < 32 .and. c /= 9 .and. c /= 12)
    end do
    if (n_control == 0) return
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c < 32 .and. c /= 9 .and. c /= 12) then
        first_binary_byte = i
        return
      end if
    end do
  end function first_binary_byte

  !> Handle *INCLUDE (file name cards) and *INCLUDE_PATH (directory cards).
  subroutine handle_include(deck, head)
    type(deck_t), intent(inout) :: deck    !< the deck source
    character(len=*), intent(in) :: head   !< '*INCLUDE' or '*INCLUDE_PATH(_RELATIVE)'
    character(len=:), allocatable :: name
    integer :: kw_file, kw_line
    logical :: got
    kw_file = deck%file
    kw_line = deck%line
    got = .false.
    do
      call read_raw_line(deck)
      if (deck%kind == LINE_BLANK) cycle
      if (deck%kind /= LINE_DATA) then
        if (deck%kind == LINE_KEYWORD) deck%reprocess = .true.
        exit
      end if
      got = .true.
      if (head == '*INCLUDE') then
        call include_named_file(deck)
        exit
      else
        name = file_name_card(deck)
        if (deck%n_paths < size(deck%paths)) then
          deck%n_paths = deck%n_paths + 1
          if (head == '*INCLUDE_PATH_RELATIVE') then
            deck%paths(deck%n_paths) = join_path(dirname(file_name(deck%file)), name)
          else
            deck%paths(deck%n_paths) = name
          end if
        end if
      end if
    end do
    if (.not. got) call input_error(location(kw_file, kw_line)//': '//trim(head), &
        'missing the file name card')
  end subroutine handle_include

  !> The file name of the current data line of an *INCLUDE (it continues on the next line when
  !> it ends with ' +').
  function file_name_card(deck) result(name)
    type(deck_t), intent(inout) :: deck    !< the deck source (at the name's first line)
    character(len=:), allocatable :: name
    name = trim(adjustl(deck%text(1:deck%length)))
    do while (len(name) > 2)
      if (name(len(name)-1:) /= ' +') exit
      name = name(1:len(name)-2)
      call read_raw_line(deck)
      if (deck%kind /= LINE_DATA) exit
      name = name//trim(adjustl(deck%text(1:deck%length)))
    end do
  end function file_name_card

  !> Include the file named on the current data line: the including file remembers that its
  !> next data lines may name more files, then the named one is opened on top of it.
  subroutine include_named_file(deck)
    type(deck_t), intent(inout) :: deck    !< the deck source (at a file-name line)
    character(len=:), allocatable :: name
    integer :: from_file, from_line, level
    logical :: ok
    level = deck%depth
    name = file_name_card(deck)
    from_file = deck%file
    from_line = deck%line
    deck%stack(level)%include_list = .true.
    call push_file(deck, name, dirname(file_name(from_file)), ok, from_file, from_line)
  end subroutine include_named_file

  !> Open a file and push it on the include stack (for an *INCLUDE: relative to base_dir,
  !> then the include paths). Missing files and recursion are reported at from_file:from_line.
  subroutine push_file(deck, name, base_dir, ok, from_file, from_line)
    type(deck_t), intent(inout) :: deck           !< the deck source
    character(len=*), intent(in) :: name          !< file name as written
    character(len=*), intent(in) :: base_dir      !< directory of the including file
    logical, intent(out) :: ok                    !< true when the file was opened
    integer, intent(in), optional :: from_file, from_line  !< location of the *INCLUDE
    character(len=:), allocatable :: path, where
    integer :: k, unit, ios
    integer(i8) :: nbytes
    logical :: exists, is_directory
    character(len=256) :: msg
    character(len=1) :: probe

    ok = .false.
    if (present(from_file)) then
      where = location(from_file, from_line)//': *INCLUDE'
    else
      where = ''
    end if
    path = join_path(base_dir, name)
    inquire(file=path, exist=exists)
    if (.not. exists .and. .not. is_absolute_path(name)) then
      do k = 1, deck%n_paths
        inquire(file=join_path(trim(deck%paths(k)), name), exist=exists)
        if (exists) then
          path = join_path(trim(deck%paths(k)), name)
          exit
        end if
      end do
    end if
    if (.not. exists) then
      if (present(from_file)) then
        call input_error(where, 'file "'//name//'" not found (looked in "'// &
            join_path(base_dir, '.')//'" and the *INCLUDE_PATH directories)')
      else
        call input_error('', 'cannot open deck "'//name//'": no such file')
      end if
      return
    end if
    inquire(file=path//'/.', exist=is_directory)
    if (is_directory) then
      call input_error(where, '"'//name//'" is a directory, not a keyword deck')
      return
    end if
    do k = 1, deck%depth            ! (the real paths: a file named two ways is one file)
      if (canonical_path(file_name(deck%stack(k)%file)) == canonical_path(path)) then
        call input_error(where, 'file "'//name//'" includes itself (recursive *INCLUDE)')
        return
      end if
    end do
    if (deck%depth == MAX_DEPTH) then
      call input_error(where, '*INCLUDE nested deeper than '//itoa(MAX_DEPTH)//' files')
      return
    end if
    open(newunit=unit, file=path, access='stream', form='unformatted', status='old', &
         action='read', iostat=ios, iomsg=msg)
    if (ios == 0) inquire(unit=unit, size=nbytes)
    if (ios /= 0 .or. nbytes < 0) then
      if (ios == 0) close(unit)
      call input_error(where, 'cannot read "'//path//'": '//trim(msg))
      return
    end if
    ! a device, a pipe or a /proc file reports no size but has bytes to read: not a deck
    ! (it would be read as empty, or forever)
    if (nbytes == 0) then
      read(unit, iostat=ios) probe
      if (ios == 0) then
        close(unit)
        call input_error(where, '"'//path//'" is not a regular file (a device, a pipe or '// &
            'a /proc file); a deck and its includes must be files')
        return
      end if
      rewind(unit)
    end if
    deck%depth = deck%depth + 1
    associate (f => deck%stack(deck%depth))
      if (allocated(f%buf)) deallocate(f%buf)
      allocate(character(len=nbytes) :: f%buf)
      if (nbytes > 0) read(unit, iostat=ios) f%buf
      close(unit)
      f%pos = 1
      ! a UTF-8 byte-order mark (some Windows editors write one) is not part of the deck
      if (nbytes >= 3) then
        if (ichar(f%buf(1:1)) == 239 .and. ichar(f%buf(2:2)) == 187 .and. &
            ichar(f%buf(3:3)) == 191) f%pos = 4
      end if
      f%line = 0
      f%garbage = 0
      f%file = add_name(path)
    end associate
    ok = .true.
  end subroutine push_file

  !> Close the innermost file.
  subroutine pop_file(deck)
    type(deck_t), intent(inout) :: deck   !< the deck source
    if (deck%depth == 0) return
    if (allocated(deck%stack(deck%depth)%buf)) deallocate(deck%stack(deck%depth)%buf)
    deck%depth = deck%depth - 1
  end subroutine pop_file

  !> Add a file to the name table; returns its index.
  integer function add_name(path)
    character(len=*), intent(in) :: path   !< the file's path
    type(name_t), allocatable :: grown(:)
    if (.not. allocated(names)) allocate(names(16))
    if (n_names == size(names)) then
      allocate(grown(2*size(names)))
      grown(1:n_names) = names(1:n_names)
      call move_alloc(grown, names)
    end if
    n_names = n_names + 1
    names(n_names)%s = path
    add_name = n_names
  end function add_name

end module mefem_deck_source
